// The state of a plan's tasks: result and log paths, task keys, done/failed/stale/missing
// (see state.hpp).
#include "replay/batch/state.hpp"

#include <algorithm>
#include <vector>

#include "replay/batch/files.hpp"
#include "replay/batch/process.hpp"
#include "replay/digest/digest.hpp"

namespace orthosonar::batch {

namespace fs = std::filesystem;
using nlohmann::json;

std::string result_dir(const Plan& plan, size_t index) {
  return (fs::path(plan.dir) / "results" / std::to_string(index)).string();
}

std::string log_path(const Plan& plan, size_t index) {
  return (fs::path(plan.dir) / "logs" / ("task-" + std::to_string(index) + ".log")).string();
}

const std::string& executable_digest() {
  static const std::string digest = [] {
    auto d = replay::sha256_file_hex(self_executable());
    return d.ok() ? *d : std::string("unknown");
  }();
  return digest;
}

Result<std::string> task_key(const Plan& plan, const Task& task, const json* known, json* inputs) {
  json k = {{"kind", plan.kind}, {"common", plan.common}, {"task", task.spec}, {"orthosonar", executable_digest()}};
  // The bytes of every input file, not its name: an edited fixture or scenario is new work.
  auto add_file = [&](const std::string& label, const std::string& path) -> Status {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec) return Error{"cannot read '" + path + "': " + ec.message()};
    const auto mtime = static_cast<int64_t>(fs::last_write_time(path, ec).time_since_epoch().count());
    std::string digest;
    if (known && known->is_object() && known->contains(label)) {
      const json& r = (*known)[label];
      if (r.value("path", std::string()) == path && r.value("size", uint64_t{0}) == size &&
          r.value("mtime_ns", int64_t{0}) == mtime)
        digest = r.value("sha256", std::string());
    }
    if (digest.empty()) {
      auto d = replay::sha256_file_hex(path);
      if (!d.ok()) return d.error();
      digest = *d;
    }
    k["inputs"][label] = digest;
    if (inputs) (*inputs)[label] = {{"path", path}, {"size", size}, {"mtime_ns", mtime}, {"sha256", digest}};
    return {};
  };
  if (plan.kind == "verify") {
    if (Status s = add_file("fixture", task.spec.at("fixture").get<std::string>()); !s.ok()) return s.error();
    if (Status s = add_file("expect", task.spec.at("expect").get<std::string>()); !s.ok()) return s.error();
  } else if (plan.kind == "golden") {
    const std::string scenario = task.spec.at("scenario").get<std::string>();
    if (Status s = add_file("scenario", scenario); !s.ok()) return s.error();
    // Its stored images: <dir>/<name>/*.png
    std::error_code ec;
    std::vector<fs::path> pngs;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(scenario).parent_path() / fs::path(scenario).stem(), ec))
      if (e.is_regular_file() && e.path().extension() == ".png") pngs.push_back(e.path());
    std::sort(pngs.begin(), pngs.end());
    for (const auto& png : pngs)
      if (Status s = add_file("image:" + png.filename().string(), png.string()); !s.ok()) return s.error();
  }
  if (const std::string model = plan.common.value("model", std::string()); !model.empty())
    if (Status s = add_file("model", model); !s.ok()) return s.error();
  // Sweep fixtures are simulated from the spec by this executable: the spec and the
  // executable's digest determine them.
  const std::string text = k.dump();
  return replay::sha256_hex(reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

std::string state_name(TaskState s) {
  switch (s) {
    case TaskState::kDone: return "done";
    case TaskState::kFailed: return "failed";
    case TaskState::kStale: return "stale";
    case TaskState::kMissing: break;
  }
  return "missing";
}

TaskStatus task_status(const Plan& plan, const Task& task, bool check_keys) {
  const fs::path dir = result_dir(plan, task.index);
  if (fs::exists(dir / "result.json")) {
    auto r = read_json_file((dir / "result.json").string());
    if (!r.ok()) return {TaskState::kMissing, r.error().message};
    if (check_keys) {
      const json known = r->value("inputs", json());
      auto key = task_key(plan, task, &known);
      if (!key.ok()) return {TaskState::kStale, "cannot compute its key: " + key.error().message};
      if (r->value("key", std::string()) != *key)
        return {TaskState::kStale, "the result was made from other inputs or another orthosonar build"};
    }
    return {TaskState::kDone, ""};
  }
  if (fs::exists(dir / "failed.json")) {
    auto f = read_json_file((dir / "failed.json").string());
    if (f.ok())
      return {TaskState::kFailed, f->value("error", std::string("?")) + " (attempt " +
                                      std::to_string(f->value("attempt", 0)) + " on " + f->value("host", std::string("?")) + ")"};
    return {TaskState::kFailed, f.error().message};
  }
  return {TaskState::kMissing, "no result"};
}

std::optional<fs::file_time_type> failure_time(const Plan& plan, size_t index) {
  std::error_code ec;
  const auto stamp = fs::last_write_time(fs::path(result_dir(plan, index)) / "failed.json", ec);
  if (ec) return std::nullopt;
  return stamp;
}

}  // namespace orthosonar::batch
