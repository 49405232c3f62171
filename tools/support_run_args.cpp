// The command-line side of the run API (see support_run_args.hpp).
#include "tools/support_run_args.hpp"

#include "tools/support_cut_inputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace orthosonar::cli {

void add_run_options(CLI::App& sub, CommonRunArgs& a) {
  sub.add_option("--systems", a.systems, "Mapping systems, comma separated (fusion, submap, inference, inference_submap)")
      ->capture_default_str();
  sub.add_option("--threads", a.threads, "Fusion threads (outputs identical for any count; default from config, 1)");
  sub.add_option("--config", a.config_path, "YAML configuration of every stage");
  sub.add_option("--rate", a.rate, "Pace the replay at R x sensor time (0: as fast as possible; changes no output)");
  sub.add_option("--mesh", a.mesh_path, "Ground-truth mesh (PLY/OBJ/STL); default: the fixture's scene");
  sub.add_option("--model", a.model_path, "Classifier model for the inference systems");
  add_allow_incomplete_flag(sub);
}

Result<RunOptions> run_options_from(const CommonRunArgs& a) {
  RunOptions o;
  if (!a.config_path.empty()) {
    auto text = read_config_text(a.config_path);
    if (!text.ok()) return text.error();
    o.config_yaml = *text;
    o.config_origin = a.config_path;
  }
  if (a.threads != 0) o.threads_override = a.threads;
  // The configuration without a fixture (checks the file and the flags now; a fixture's
  // recorded values are layered under them when it is opened).
  auto c = effective_config({}, o);
  if (!c.ok()) return c.error();
  o.config = *c;
  if (a.rate < 0.0) return Error{"--rate must be >= 0"};
  o.rate = a.rate;
  o.mesh_path = a.mesh_path;
  o.model_path = a.model_path;
  o.systems.clear();
  std::stringstream ss(a.systems);
  std::string name;
  while (std::getline(ss, name, ','))
    if (!name.empty()) o.systems.push_back(name);
  if (o.systems.empty()) return Error{"--systems is empty"};
  return o;
}

void print_progress(const std::string& label, double fraction, const std::string& detail) {
  const double f = std::clamp(fraction, 0.0, 1.0);
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(f * kWidth);
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r%s [%s] %3d%%  %s   ", label.c_str(), bar.c_str(), static_cast<int>(f * 100.0),
               detail.c_str());
  if (f >= 1.0) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}


RunControl progress_bar_control(const std::string& label, bool show) {
  RunControl c;
  if (!show) return c;
  c.progress = [label](const Progress& p) {
    if (std::isnan(p.fraction)) return;
    print_progress(label, p.fraction,
                   p.fraction >= 1.0 ? std::string("done") : std::to_string(p.events) + " events");
  };
  return c;
}

}  // namespace orthosonar::cli
