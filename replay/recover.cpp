// `orthosonar recover`: a cut recording rewritten whole (see recover.hpp).
#include "replay/recover.hpp"

#include <filesystem>

namespace orthosonar::replay {

Result<RecoverResult> recover_fixture(const std::string& in, const std::string& out, const WriterOptions& options) {
  auto src = FixtureSource::open(in);
  if (!src.ok()) return src.error();
  RecoverResult r;
  r.input = (*src)->recovery();
  FixtureMetadata metadata = (*src)->metadata();
  if (auto cut = cut_input_warning(in, r.input)) metadata["recovered_from"] = *cut;
  const std::string tmp = out + ".partial";
  auto fail = [&](const Error& e) -> Result<RecoverResult> {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return e;
  };
  {
    auto writer = FixtureWriter::open(tmp, metadata, options);
    if (!writer.ok()) return writer.error();
    // Attachments first, as the recorder writes them (FixtureWriter::attach).
    for (const Attachment& a : (*src)->attachments()) {
      if (Status s = (*writer)->attach(a); !s.ok()) return fail(s.error());
      ++r.attachments;
    }
    for (;;) {
      hal::Pulled p = (*src)->next();
      if (p.error) return fail(*p.error);
      if (p.end_of_stream || !p.event) break;
      if (Status s = (*writer)->write(*p.event); !s.ok()) return fail(s.error());
      ++r.events;
    }
    if (Status s = (*writer)->close(); !s.ok()) return fail(s.error());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, out, ec);
  if (ec) return fail(Error{"cannot rename '" + tmp + "' to '" + out + "': " + ec.message()});
  return r;
}

}  // namespace orthosonar::replay
