#pragma once
// ROS message definitions and the two wire encodings of ROS messages, for any type whose
// definition text a file carries: ROS 1 bags and ros1msg MCAP schemas (the `ros1`
// encoding), ROS 2 MCAP recordings (`ros2msg` schemas, the `cdr` encoding: an
// encapsulation header then XCDR1 plain CDR, little or big endian, with alignment).
// The decoder is driven by the definition, so other versions of a type (extra fields,
// other field orders) decode as long as the fields the importer reads exist.
// Errors name the type, the field path and the byte offset at fault.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::replay::rosmsg {

enum class Dialect { kRos1, kRos2 };    // how the definition text is written
enum class Encoding { kRos1, kCdr };    // how messages are serialised

enum class Prim : uint8_t {
  kBool, kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kInt64, kUint64,
  kFloat32, kFloat64, kString, kTime, kDuration, kMessage,
};

struct Field {
  std::string name;
  Prim prim = Prim::kUint8;
  std::string type;          // kMessage: the resolved full name, e.g. "std_msgs/Header";
                             // otherwise the builtin as written ("float64", "byte", "string<=8";
                             // "time"/"duration" for builtin_interfaces Time/Duration)
  int array = -1;            // -1 scalar, 0 variable length, n > 0 fixed length n
  uint32_t upper_bound = 0;  // ROS 2 bounded sequences/strings (0: unbounded); checked on decode
};

struct Constant {
  std::string type, name, value;  // value as written
};

struct MsgSpec {
  std::string name;  // full name "pkg/Type"
  std::vector<Field> fields;
  std::vector<Constant> constants;
};

// A type and every type it depends on, parsed from a definition text (the root type's
// fields, then sections "====...====\nMSG: pkg/Type"). Resolves "Header" to
// std_msgs/Header, unqualified names to the root's package, "pkg/msg/Type" to
// "pkg/Type", ROS 2 "builtin_interfaces/Time"/"Duration" to kTime/kDuration (int32 sec,
// uint32 nanosec) and ROS 1 `time`/`duration` likewise (uint32/int32 sec, nsec); accepts
// comments, constants, ROS 2 default values, bounded strings and sequences. A field
// whose type has no section is an error naming the type and field.
class Schema {
 public:
  static Result<Schema> parse(std::string_view root_type, std::string_view text, Dialect dialect);
  const std::string& root() const { return root_; }
  const MsgSpec* find(std::string_view type) const;
  const std::map<std::string, MsgSpec, std::less<>>& types() const { return types_; }
  Dialect dialect() const { return dialect_; }
  // The ROS 1 MD5 sum of the root type (genmsg's rule: constants, then fields, nested
  // message types replaced by their own MD5), 32 lowercase hex digits.
  std::string md5() const;

 private:
  std::string root_;
  Dialect dialect_ = Dialect::kRos1;
  std::map<std::string, MsgSpec, std::less<>> types_;
};

// A decoded message: a tree of values. Arrays of numbers are kept as arrays of numbers
// (uint8[] / int8[] as a byte span into the caller's buffer, not copied).
class Value {
 public:
  enum class Kind : uint8_t { kNumber, kString, kTime, kMessage, kArray, kBytes };
  Kind kind() const { return kind_; }
  // Field of a message by dotted path ("fire_msg.gain", "header.stamp"); nullptr when
  // absent (or when this is not a message).
  const Value* find(std::string_view path) const;
  // Numbers (bool, integers, floats) as double / int64 (exact for integers within 2^53;
  // as_int is exact for every integer type except uint64 above INT64_MAX).
  double as_double() const { return number_; }
  int64_t as_int() const { return integer_; }
  bool is_integer() const { return is_integer_; }
  const std::string& as_string() const { return string_; }
  // kTime / kDuration: nanoseconds (sec * 1e9 + nsec, exact).
  int64_t as_ns() const { return integer_; }
  // kArray: elements (numbers of a numeric array except bytes; strings; messages).
  const std::vector<Value>& elements() const { return elements_; }
  // kBytes: uint8[] / int8[] / char[] / byte[] contents (a view into the decoded buffer).
  std::span<const uint8_t> bytes() const { return bytes_; }
  // kMessage: fields in definition order.
  const std::vector<std::pair<std::string, Value>>& fields() const { return fields_; }
  // Numeric arrays (kArray of numbers or kBytes) as doubles.
  std::vector<double> as_doubles() const;

  // Construction (the decoder, tests).
  static Value number(double d, int64_t i, bool integer);
  static Value string(std::string s);
  static Value time(int64_t ns);
  static Value message(std::vector<std::pair<std::string, Value>> fields);
  static Value array(std::vector<Value> elements);
  // signed_elements: int8[] (ROS 1 byte[]), so as_doubles() gives -128..127.
  static Value bytes(std::span<const uint8_t> b, bool signed_elements = false);

 private:
  Kind kind_ = Kind::kNumber;
  double number_ = 0.0;
  int64_t integer_ = 0;
  bool is_integer_ = false;
  std::string string_;
  std::vector<Value> elements_;
  std::span<const uint8_t> bytes_;
  std::vector<std::pair<std::string, Value>> fields_;
};

// Decodes one message of the schema's root type. The whole buffer must be consumed
// (trailing bytes are an error, except CDR's final alignment padding). Lengths are checked
// against the remaining bytes before anything is allocated.
Result<Value> decode(const Schema& schema, Encoding encoding, const uint8_t* data, size_t size);

// Serialises a message field by field in definition order (callers write the fields of
// their type in order; the schema is not consulted). For kCdr the 4-byte encapsulation
// header (CDR little endian: 00 01 00 00) comes first and every primitive is aligned to its
// size relative to the end of that header, as rmw/Fast-CDR write it.
class Writer {
 public:
  explicit Writer(Encoding encoding);
  Encoding encoding() const { return encoding_; }
  void boolean(bool v);
  void i8(int8_t v);
  void u8(uint8_t v);
  void i16(int16_t v);
  void u16(uint16_t v);
  void i32(int32_t v);
  void u32(uint32_t v);
  void i64(int64_t v);
  void u64(uint64_t v);
  void f32(float v);
  void f64(double v);
  void string(std::string_view s);
  // A time: ROS 1 uint32 sec, uint32 nsec; CDR int32 sec, uint32 nanosec. ns >= 0.
  void time(int64_t ns);
  // The length prefix of a variable-length array (uint32, aligned in CDR).
  void sequence_length(uint32_t n);
  // Raw bytes of a uint8[] (after sequence_length) or uint8[N].
  void raw(const uint8_t* data, size_t n);
  // A std_msgs/Header: ROS 1 (uint32 seq, time stamp, string frame_id); ROS 2 (stamp,
  // frame_id, no seq).
  void header(uint32_t seq, int64_t stamp_ns, std::string_view frame_id);
  const std::vector<uint8_t>& bytes() const { return buf_; }
  std::vector<uint8_t> take() { return std::move(buf_); }

 private:
  void align(size_t n);
  Encoding encoding_;
  std::vector<uint8_t> buf_;
};

}  // namespace orthosonar::replay::rosmsg
