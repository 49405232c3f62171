// Option files as key tables: per YAML map, each key's reader and valid range, so every
// value is checked before it reaches a stage and an error names the key. One machinery for
// the run configuration (replay/run/run_config.cpp) and the simulator's (hal/sim/sim_config.cpp),
// each with its own wording (KeyTables::Wording).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/geometry.hpp"
#include "core/result.hpp"

namespace orthosonar::config {

struct Entry;
using Table = std::map<std::string, Entry>;
using Reader = std::function<Status(const YAML::Node&, const std::string& where)>;
using Check = std::function<Status(const std::string& where)>;
struct Entry {
  Reader read;
  Check check;                        // the current value is in range (null: not checked, an alias or a map)
  std::string range;                  // human-readable valid range ("" for a nested map)
  std::string bad;                    // one out-of-range YAML value (tests)
  std::function<Table()> children;    // nested map
};

// One key of a table with its valid range, for documentation and tests.
struct KeyRange {
  std::string key;        // "vehicle.step_s"
  std::string range;      // "[0.0001, 1]"
  std::string bad_value;  // a YAML value the key rejects
};

enum class Parity { kAny, kOdd, kEven };

// A number as a range or a message shows it (10 significant digits).
std::string number_text(double v);

// The entries and the walk of one kind of option file, worded its way.
class KeyTables {
 public:
  struct Wording {
    std::string prefix;                // starts every message: "config: ", "sim config: "
    bool integer_range_colon = false;  // "... is outside its valid range: <range>" for an integer
    bool choice_names_value = false;   // "'k' is 'v', expected one of R" (else "'k' must be one of R")
    bool pose_names_part = false;      // "'k' translation is outside R" / "angle ..." (else "'k' is outside R")
  };
  explicit KeyTables(Wording wording) : w_(std::move(wording)) {}

  // An error worded for this kind of file: the prefix, then `text`.
  Error error(const std::string& text) const { return Error{w_.prefix + text}; }

  // A real number in [lo, hi] (lo_open / hi_open exclude the bound), never NaN or infinite.
  // `targets` are set together; `checked` says whether check() looks at the first target
  // under this key (false for an alias of other keys).
  Entry real(std::vector<double*> targets, double lo, double hi, bool lo_open = false, bool hi_open = false,
             bool checked = true) const;
  Entry real(double& target, double lo, double hi, bool lo_open = false, bool hi_open = false) const {
    return real(std::vector<double*>{&target}, lo, hi, lo_open, hi_open);
  }

  // An integer in [lo, hi] stored in T, of the given parity.
  template <class T>
  Entry integer(std::vector<T*> targets, int64_t lo, int64_t hi, Parity parity = Parity::kAny,
                bool checked = true) const {
    Entry e;
    e.range = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" +
              (parity == Parity::kOdd ? ", odd" : parity == Parity::kEven ? ", even" : "");
    e.bad = std::to_string(lo - 1);
    auto in_range = [lo, hi, parity](int64_t v) {
      return v >= lo && v <= hi && (parity != Parity::kOdd || v % 2 != 0) && (parity != Parity::kEven || v % 2 == 0);
    };
    e.read = [w = w_, targets, in_range, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
      int64_t v = 0;
      try {
        v = n.as<int64_t>();
      } catch (const YAML::Exception&) {
        return Error{w.prefix + "'" + where + "' must be an " + range};
      }
      if (!in_range(v)) return integer_out_of_range(w, where, std::to_string(v), range);
      for (T* t : targets) *t = static_cast<T>(v);
      return {};
    };
    if (checked)
      e.check = [w = w_, t = targets.front(), in_range, range = e.range](const std::string& where) -> Status {
        if (!in_range(static_cast<int64_t>(*t))) return integer_out_of_range(w, where, std::to_string(*t), range);
        return {};
      };
    return e;
  }
  template <class T>
  Entry integer(T& target, int64_t lo, int64_t hi, Parity parity = Parity::kAny) const {
    return integer(std::vector<T*>{&target}, lo, hi, parity);
  }

  Entry boolean(bool& target) const;
  // One of the names in `range` ("a, b, c"); `set` applies a name and says whether it is one.
  Entry choice(std::string range, std::function<bool(const std::string&)> set) const;
  // One of an enum's `values` by its name (`name(value)`), the range listing the names in
  // that order.
  template <class E, size_t N, class Name>
  Entry choice_of(E& target, const E (&values)[N], Name name) const {
    std::string range;
    for (E v : values) range += (range.empty() ? "" : ", ") + std::string(name(v));
    return choice(std::move(range), [&target, all = std::to_array(values), name](const std::string& s) {
      for (E v : all)
        if (s == name(v)) {
          target = v;
          return true;
        }
      return false;
    });
  }
  // A mount pose "x y z roll pitch yaw": six finite numbers, |x|,|y|,|z| <= 100 m, angles in [-2 pi, 2 pi].
  Entry pose(SE3& target) const;
  // A nested map, its table made when it is read.
  Entry nested(std::function<Table()> make) const;

  // Applies the keys of `node` (a map at `prefix`, "" for the root) that `now` selects (null:
  // all); every key must be in `table`.
  Status apply(const YAML::Node& node, const Table& table, const std::string& prefix,
               const std::function<bool(const std::string&)>& now = nullptr) const;
  // Every checked key of `table` holds a value in its range.
  static Status check(const Table& table, const std::string& prefix = "");
  // Every key of `table` with its range, nested keys as "a.b".
  static std::vector<KeyRange> ranges(const Table& table);

 private:
  static Status integer_out_of_range(const Wording& w, const std::string& where, const std::string& value,
                                     const std::string& range);
  Wording w_;
};

}  // namespace orthosonar::config
