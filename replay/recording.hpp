#pragma once
// RecordingSource: an EventSource that passes through every event of another source and
// appends it to a fixture in consumption order (SPEC §11: "every event a source produced,
// in the order the core consumed it"). The core sees exactly what the inner source
// yields; a recording failure is reported as an error from next().
#include <memory>
#include <string>

#include "hal/event_source.hpp"
#include "replay/fixture.hpp"

namespace orthosonar::replay {

class RecordingSource final : public hal::EventSource {
 public:
  static Result<std::unique_ptr<RecordingSource>> open(std::unique_ptr<hal::EventSource> inner,
                                                       const std::string& path,
                                                       const FixtureMetadata& metadata,
                                                       const WriterOptions& options = {},
                                                       const std::vector<Attachment>& attachments = {});
  // `attachments` (e.g. the scene of the fixture whose metadata a live run copies) are
  // written before the first event, so the recording is as self-contained as its source.
  // Pulls from the inner source and records the event before handing it on. At the end
  // of the stream the fixture is closed (summary and footer written). An inner error is
  // passed on unchanged and the recording continues with whatever follows.
  hal::Pulled next() override;
  std::string describe() const override;
  // Closes the fixture early (also done by the destructor, ignoring errors).
  Status close();
  uint64_t recorded() const { return recorded_; }

 private:
  RecordingSource(std::unique_ptr<hal::EventSource> inner, std::unique_ptr<FixtureWriter> writer,
                  std::string path)
      : inner_(std::move(inner)), writer_(std::move(writer)), path_(std::move(path)) {}
  std::unique_ptr<hal::EventSource> inner_;
  std::unique_ptr<FixtureWriter> writer_;
  std::string path_;
  uint64_t recorded_ = 0;
  bool closed_ = false;
};

}  // namespace orthosonar::replay
