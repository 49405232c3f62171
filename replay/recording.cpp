#include "replay/recording.hpp"

namespace orthosonar::replay {

Result<std::unique_ptr<RecordingSource>> RecordingSource::open(std::unique_ptr<hal::EventSource> inner,
                                                               const std::string& path,
                                                               const FixtureMetadata& metadata,
                                                               const WriterOptions& options,
                                                               const std::vector<Attachment>& attachments) {
  auto w = FixtureWriter::open(path, metadata, options);
  if (!w) return w.error();
  for (const auto& a : attachments)
    if (auto s = (*w)->attach(a); !s) return s.error();
  return std::unique_ptr<RecordingSource>(new RecordingSource(std::move(inner), std::move(w.value()), path));
}

hal::Pulled RecordingSource::next() {
  hal::Pulled p = inner_->next();
  if (p.event && !closed_) {
    if (auto s = writer_->write(*p.event); !s) return hal::Pulled::fail(s.error());
    ++recorded_;
  } else if (p.end_of_stream && !closed_) {
    if (auto s = close(); !s) return hal::Pulled::fail(s.error());
  }
  return p;
}

std::string RecordingSource::describe() const { return inner_->describe() + " -> record:" + path_; }

Status RecordingSource::close() {
  if (closed_) return {};
  closed_ = true;
  return writer_->close();
}

}  // namespace orthosonar::replay
