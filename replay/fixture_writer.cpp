// FixtureWriter: our event channels as ros1 messages, written by the one MCAP writer
// (replay/mcap_generic.hpp). Layout: magic, Header, Metadata "orthosonar", Attachments
// (when attach() is called, e.g. the simulator's scene), then per first use of a channel
// its Schema and Channel records, Chunks each followed by its Message Index records,
// Data End, the summary, Footer, magic. Channel ids are the Channel values (from 0),
// schema ids those of replay/ros1_codec.hpp (1..6).
#include <string>

#include "core/canonical.hpp"
#include "orthosonar/version.hpp"
#include "replay/fixture.hpp"
#include "replay/mcap_format.hpp"
#include "replay/mcap_generic.hpp"
#include "replay/ros1_codec.hpp"

namespace orthosonar::replay {
namespace {

class McapFixtureWriter final : public FixtureWriter {
 public:
  McapFixtureWriter(std::unique_ptr<mcap::GenericWriter> w, std::string path) : w_(std::move(w)), path_(std::move(path)) {
    // Schemas in id order (the channels' schemas first appear in that order), then one
    // channel per Channel value: add_* return exactly the ids of ros1_codec.hpp.
    uint16_t schema_id = 0;
    for (int c = 0; c < kChannelCount; ++c) {
      const auto& s = ros1::schema_for(static_cast<Channel>(c));
      if (s.id > schema_id)
        schema_id = w_->add_schema(std::string(s.name), std::string(mcap::kSchemaEncoding), std::string(s.text));
      w_->add_channel(schema_id, channel_topic(static_cast<Channel>(c)), std::string(mcap::kMessageEncoding));
    }
  }

  Status write(const Event& e) override {
    if (closed_) return reject("write after close");
    if (e.stamp.ns() < 0) return reject("negative event stamp " + std::to_string(e.stamp.ns()) + " ns");
    if (e.sequence > UINT32_MAX) return reject("sequence " + std::to_string(e.sequence) + " exceeds uint32");
    const auto ch = static_cast<size_t>(e.channel);
    if (ch >= kChannelCount) return reject("unknown channel " + std::to_string(ch));
    msg_.clear();
    if (auto s = ros1::encode(e, msg_); !s)
      return reject(std::string("cannot encode event on ") + channel_topic(e.channel) + " (sequence " +
                    std::to_string(e.sequence) + "): " + s.error().message);
    const auto stamp = static_cast<uint64_t>(e.stamp.ns());
    return w_->write(static_cast<uint16_t>(ch), static_cast<uint32_t>(e.sequence), stamp, stamp, msg_.bytes().data(),
                     msg_.size());
  }

  Status attach(const Attachment& a) override {
    if (closed_) return reject("attach after close");
    return w_->attach(a);
  }

  Status close() override {
    closed_ = true;
    return w_->close();
  }

 private:
  // An event that cannot be stored: rejected, nothing written, the file stays valid.
  Status reject(const std::string& what) const { return Error{path_ + ": " + what}; }

  std::unique_ptr<mcap::GenericWriter> w_;
  std::string path_;
  CanonicalWriter msg_;
  bool closed_ = false;
};

}  // namespace

Result<std::unique_ptr<FixtureWriter>> FixtureWriter::open(const std::string& path,
                                                           const FixtureMetadata& metadata,
                                                           const WriterOptions& options) {
  mcap::GenericWriterOptions o;
  o.profile = mcap::kProfile;
  o.library = std::string("orthosonar ") + kVersion;
  o.compression = options.compress ? "zstd" : "";
  o.zstd_level = options.zstd_level;
  o.chunk_max_log_ns = options.chunk_max_stream_ns;
  o.chunk_max_bytes = options.chunk_max_bytes;
  o.first_channel_id = 0;
  auto w = mcap::GenericWriter::open(path, o);
  if (!w) return w.error();
  if (auto s = (*w)->metadata(std::string(mcap::kMetadataName), metadata); !s) return s.error();
  return std::unique_ptr<FixtureWriter>(std::make_unique<McapFixtureWriter>(std::move(*w), path));
}

}  // namespace orthosonar::replay
