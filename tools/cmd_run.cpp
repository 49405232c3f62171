// `orthosonar run --devices devices.yaml --record out.mcap -o out/`: the pipeline on live
// devices. Every event the core consumes is recorded, in consumption order, so
// `orthosonar replay out.mcap` reproduces the run's outputs bit for bit. Live stamps come
// from the tool's monotonic clock (from the start of the run). SIGINT/SIGTERM end the run
// cleanly: the pipeline finishes, outputs are written and the recording is finalised.
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "hal/drivers/live_source.hpp"
#include "orthosonar/version.hpp"
#include "replay/fixture/fixture.hpp"
#include "replay/fixture/recording.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

std::atomic<hal::drivers::LiveSource*> g_live{nullptr};
std::atomic<bool> g_stop_requested{false};
extern "C" void run_on_signal(int) {
  g_stop_requested.store(true);
  if (auto* l = g_live.load()) l->stop();
}

// Passes events through and notes when the last one arrived (for --idle-stop).
class Watched final : public hal::EventSource {
 public:
  explicit Watched(std::unique_ptr<hal::EventSource> inner) : inner_(std::move(inner)) {}
  hal::Pulled next() override {
    auto p = inner_->next();
    if (p.event) {
      count_.fetch_add(1);
      last_ns_.store(std::chrono::steady_clock::now().time_since_epoch().count());
    }
    return p;
  }
  std::string describe() const override { return inner_->describe(); }
  uint64_t count() const { return count_.load(); }
  int64_t last_ns() const { return last_ns_.load(); }

 private:
  std::unique_ptr<hal::EventSource> inner_;
  std::atomic<uint64_t> count_{0};
  std::atomic<int64_t> last_ns_{0};
};

struct RunArgs {
  std::string devices;
  std::string record;
  std::string out_dir = "out/run";
  double duration_s = 0.0;
  double idle_stop_s = 0.0;
  std::string metadata_from;
  bool quiet = false;
  CommonRunArgs run;
};

int run_live(const RunArgs& a) {
  using namespace hal::drivers;
  // Handlers first: a signal during start-up still ends the run cleanly.
  std::signal(SIGINT, run_on_signal);
  std::signal(SIGTERM, run_on_signal);
  auto options = run_options_from(a.run);
  if (!options) {
    std::cerr << "orthosonar run: " << options.error().message << "\n";
    return 2;
  }
  auto config = load_live_config(a.devices);
  if (!config) {
    std::cerr << "orthosonar run: " << config.error().message << "\n";
    return 2;
  }
  replay::FixtureMetadata meta;
  std::vector<replay::Attachment> scene_files;  // the --metadata-from fixture's embedded scene
  if (!a.metadata_from.empty()) {
    auto f = replay::FixtureSource::open(a.metadata_from);
    if (!f) {
      std::cerr << "orthosonar run: " << f.error().message << "\n";
      return 2;
    }
    note_input(a.metadata_from, (*f)->recovery());
    meta = (*f)->metadata();
    scene_files = (*f)->attachments();
  }
  std::ifstream yin(a.devices);
  std::stringstream yaml;
  yaml << yin.rdbuf();
  meta["source"] = "live";
  meta["live_devices_yaml"] = yaml.str();
  meta["live_clock"] = "monotonic, ns since the start of the run";
  meta["live_start_unix_ns"] = std::to_string(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count());
  meta["software_version"] = kVersion;
  // defaults < the --metadata-from fixture's extrinsics and mission start < --config < flags
  RunOptions ro = *options;
  ConfigSources sources;
  auto run_config = effective_config(meta, ro, &sources, scene_files);
  if (!run_config.ok()) {
    std::cerr << "orthosonar run: " << run_config.error().message << "\n";
    return 2;
  }
  ro.config = *run_config;

  if (Status s = clear_run_verdicts(a.out_dir); !s.ok()) {
    std::cerr << "orthosonar run: " << s.error().message << "\n";
    return 2;
  }
  auto live_owned = std::make_unique<LiveSource>(*config);
  LiveSource* live = live_owned.get();
  if (Status s = live->start(); !s.ok()) {
    std::cerr << "orthosonar run: " << s.error().message << "\n";
    return 2;
  }
  if (a.duration_s > 0) live->set_deadline(live->now() + Time::from_seconds(a.duration_s));
  auto watched_owned = std::make_unique<Watched>(std::move(live_owned));
  Watched* watched = watched_owned.get();
  std::unique_ptr<hal::EventSource> source = std::move(watched_owned);
  replay::RecordingSource* recording = nullptr;
  if (!a.record.empty()) {
    auto r = replay::RecordingSource::open(std::move(source), a.record, meta, {}, scene_files);
    if (!r) {
      std::cerr << "orthosonar run: " << r.error().message << "\n";
      return 2;
    }
    recording = r->get();
    source = std::move(*r);
  }
  g_live.store(live);
  if (g_stop_requested.load()) live->stop();
  std::atomic<bool> done{false};
  std::thread idle([&] {
    while (!done.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (a.idle_stop_s > 0 && watched->count() > 0) {
        const int64_t quiet_ns = std::chrono::steady_clock::now().time_since_epoch().count() - watched->last_ns();
        if (static_cast<double>(quiet_ns) * 1e-9 > a.idle_stop_s) live->stop();
      }
    }
  });
  std::string note;
  const auto mesh = load_truth_mesh(meta, ro.mesh_path, note, scene_files);
  auto result = run_source(*source, meta, ro, mesh);
  done.store(true);
  idle.join();
  live->stop();
  Status closed = recording ? recording->close() : Status::Ok();
  const LiveReport report = live->report();
  std::filesystem::create_directories(a.out_dir);
  std::ofstream(std::filesystem::path(a.out_dir) / "live_faults.json") << report_json(report) << "\n";
  g_live.store(nullptr);
  if (!closed.ok()) {
    std::cerr << "orthosonar run: recording: " << closed.error().message << "\n";
    return 2;
  }
  if (!result) {
    std::cerr << "orthosonar run: " << result.error().message << "\n";
    return 2;
  }
  result->mesh_note = note;
  result->config_sources = sources;
  if (Status s = write_run_outputs(*result, ro, a.out_dir); !s.ok()) {
    std::cerr << "orthosonar run: " << s.error().message << "\n";
    return 2;
  }
  if (!a.quiet) {
    std::cerr << "live run: " << report.events_consumed << " events consumed";
    for (const auto& d : report.devices)
      std::cerr << "; " << d.name << " " << d.health.messages_ok << " ok, " << d.health.messages_malformed << " malformed, "
                << d.health.reconnects << " reconnects, " << d.gaps.size() << " gaps";
    uint64_t dropped = 0;
    for (auto n : report.queue.dropped) dropped += n;
    std::cerr << "; queue drops " << dropped << (a.record.empty() ? "" : "; recorded " + a.record) << "; outputs in "
              << a.out_dir << "\n";
  }
  std::cout << result->digest.overall_hex << "\n";
  return 0;
}

const bool registered_run = register_command(
    {"run", "Run the pipeline on live devices (devices.yaml), recording every consumed event",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<RunArgs>();
       sub.add_option("--devices", a->devices, "Device configuration (docs/DRIVERS.md)")->required();
       sub.add_option("--record", a->record, "Record every consumed event to this fixture (.mcap)");
       sub.add_option("-o,--out", a->out_dir, "Output directory")->capture_default_str();
       sub.add_option("--duration", a->duration_s, "Stop after this many seconds (0: until Ctrl-C)")->capture_default_str();
       sub.add_option("--idle-stop", a->idle_stop_s, "Stop when no event arrived for this many seconds (0: never)")
           ->capture_default_str();
       sub.add_option("--metadata-from", a->metadata_from,
                      "Copy fixture metadata (scene, extrinsics) from this fixture, e.g. the one being emulated");
       sub.add_flag("-q,--quiet", a->quiet, "Print only the digest");
       add_run_options(sub, a->run);
       return [a] { return run_live(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
