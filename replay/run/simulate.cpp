// A simulated mission written to a fixture (see simulate.hpp).
#include "replay/run/simulate.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "hal/sim/sonar_fan.hpp"
#include "replay/fixture/fixture.hpp"

namespace orthosonar::run {

Result<SimulateCounts> simulate_to_fixture(sim::Simulator& simulator, const SimulateOptions& a) {
  std::unique_ptr<replay::FixtureWriter> writer;
  // Written as <out>.partial and renamed when complete, so a reader never sees a fixture
  // that is still being written (or the half of one an interrupted run left).
  const std::string partial = a.out + ".partial";
  if (!a.out.empty()) {
    replay::WriterOptions wo;
    wo.zstd_level = a.zstd_level;
    auto w = replay::FixtureWriter::open(partial, simulator.metadata(), wo);
    if (!w) return w.error();
    writer = std::move(*w);
    // The scene goes into the fixture (mesh, route, classes): replay needs no scene file.
    auto files = sim::embed_scene(simulator.scene());
    if (!files) return files.error();
    for (auto& f : *files)
      if (Status s = writer->attach({f.name, f.media_type, std::move(f.data)}); !s) return s.error();
  }
  std::vector<double> snaps = a.snapshot_at_s;
  std::sort(snaps.begin(), snaps.end());
  std::array<size_t, 2> next_snap{0, 0};
  SimulateCounts counts;
  while (true) {
    hal::Pulled p = simulator.next();
    if (p.error) return *p.error;
    if (p.end_of_stream) break;
    const Event& e = *p.event;
    ++counts.per_channel[static_cast<size_t>(e.channel)];
    ++counts.events;
    if (!a.snapshot_dir.empty() && (e.channel == Channel::kSonarHorizontal || e.channel == Channel::kSonarVertical)) {
      const auto& ping = std::get<SonarPing>(e.payload);
      const size_t m = static_cast<size_t>(ping.mount);
      if (next_snap[m] < snaps.size() && e.stamp.seconds() >= snaps[next_snap[m]]) {
        char name[96];
        std::snprintf(name, sizeof name, "%s_%s_%07.1fs.png", simulator.scene().name.c_str(),
                      m == 0 ? "horizontal" : "vertical", snaps[next_snap[m]]);
        std::filesystem::create_directories(a.snapshot_dir);
        const auto path = (std::filesystem::path(a.snapshot_dir) / name).string();
        if (Status s = sim::write_fan_png(ping, path, 800); !s) return s.error();
        ++next_snap[m];
      }
    }
    if (writer) {
      if (Status s = writer->write(e); !s) return s.error();
    }
  }
  if (writer) {
    if (Status s = writer->close(); !s) return s.error();
    std::error_code ec;
    std::filesystem::rename(partial, a.out, ec);
    if (ec) return Error{"cannot rename '" + partial + "' to '" + a.out + "': " + ec.message()};
  }
  return counts;
}

}  // namespace orthosonar::run
