// Merging a plan's results into the one-machine outputs and JUnit XML (see merge.hpp).
#include "replay/batch/merge.hpp"

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "reports/html.hpp"
#include "replay/batch/files.hpp"
#include "replay/batch/state.hpp"
#include "replay/batch/sweep_outputs.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::batch {

namespace fs = std::filesystem;
using nlohmann::json;

std::string xml_escape(const std::string& s) {
  // XML 1.0 allows tab, newline, carriage return and nothing else below 0x20; the five
  // markup characters are escaped as for HTML (&#39; is XML's too).
  std::string text = s;
  for (char& ch : text)
    if (static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\n' && ch != '\r') ch = '?';
  return reports::html_escape(text);
}

namespace {

struct Gathered {
  std::vector<std::optional<json>> results;  // per task, when done and current
  std::vector<std::string> problems;         // one line per missing/failed/stale task
};

Gathered gather(const Plan& plan) {
  Gathered g;
  for (const auto& t : plan.tasks) {
    TaskStatus st = task_status(plan, t, true);
    if (st.state == TaskState::kDone) {
      auto r = read_json_file((fs::path(result_dir(plan, t.index)) / "result.json").string());
      if (r.ok()) {
        g.results.push_back(std::move(*r));
        continue;
      }
      st = {TaskState::kMissing, r.error().message};  // removed or rewritten meanwhile
    }
    g.results.push_back(std::nullopt);
    g.problems.push_back("task " + std::to_string(t.index) + " (" + t.name + "): " + state_name(st.state) + ": " +
                         st.detail + "; log " + log_path(plan, t.index));
  }
  return g;
}

// The tasks whose inputs were cut short (a result's "input_cut"), named on stderr and
// noted as cut inputs: merge exits 1 for them unless --allow-incomplete (issue 40).
json note_cut_tasks(const Plan& plan, const Gathered& g, const MergeOptions& o) {
  json named = json::array();
  for (const auto& t : plan.tasks) {
    const auto& r = g.results[t.index];
    if (!r || !r->contains("input_cut")) continue;
    const std::string why = r->value("input_cut", std::string());
    named.push_back({{"index", t.index}, {"name", t.name}, {"input_cut", why}});
    const std::string warning = "batch task " + std::to_string(t.index) + " (" + t.name + "): " + why;
    if (o.on_cut_input) o.on_cut_input(warning);
    else *o.log << "warning: " << warning << "\n";
  }
  return named;
}

void report_problems(const Plan& plan, const Gathered& g, std::ostream& log) {
  log << "orthosonar batch merge: " << g.problems.size() << " of " << plan.tasks.size() << " task results missing (plan "
      << plan.dir << "):\n";
  for (const auto& p : g.problems) log << "  " << p << "\n";
  log << "re-run them (a re-submitted plan skips the tasks already done), then merge again\n";
}

Status copy_tree(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::create_directories(to, ec);
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::overwrite_existing, ec);
  if (ec) return Error{"cannot copy '" + from.string() + "' to '" + to.string() + "': " + ec.message()};
  return {};
}

int merge_sweep(const Plan& plan, const Gathered& g, const fs::path& out, const MergeOptions& o) {
  if (!g.problems.empty()) {
    report_problems(plan, g, *o.log);
    return 2;
  }
  note_cut_tasks(plan, g, o);
  // One report per (scene, seed), in the plan's order; cells in task order = grid order.
  std::vector<run::SweepReport> reports;
  std::vector<uint64_t> seeds;
  std::vector<std::optional<size_t>> reference_task;
  std::map<std::pair<std::string, uint64_t>, size_t> slot;
  for (const auto& t : plan.tasks) {
    const auto key = std::make_pair(t.spec.at("scene").get<std::string>(), t.spec.at("seed").get<uint64_t>());
    const json& r = *g.results[t.index];
    auto [it, fresh] = slot.emplace(key, reports.size());
    if (fresh) {
      run::SweepReport rep;
      rep.metadata = r.at("metadata").get<std::map<std::string, std::string>>();
      const auto sc = rep.metadata.find("scene");
      rep.scene = sc == rep.metadata.end() ? "?" : sc->second;
      rep.fusion_runtime = run::runtime_stats_from_json(r.at("fusion_runtime"));
      rep.inference_runtime = run::runtime_stats_from_json(r.at("inference_runtime"));
      rep.stream_s = r.at("stream_s").get<double>();
      rep.fuse_wall_s = r.at("fuse_wall_s").get<double>();
      rep.input_cut = r.value("input_cut", std::string());
      reports.push_back(std::move(rep));
      seeds.push_back(key.second);
      reference_task.push_back(std::nullopt);
    }
    for (const auto& c : r.at("cells")) {
      auto cell = run::cell_result_from_json(c);
      if (!cell.ok()) {
        *o.log << "orthosonar batch merge: " << result_dir(plan, t.index) << "/result.json: " << cell.error().message << "\n";
        return 2;
      }
      reports[it->second].cells.push_back(std::move(*cell));
    }
    if (t.spec.value("reference", false)) reference_task[it->second] = t.index;
  }
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    *o.log << "orthosonar batch merge: cannot create '" << out.string() << "': " << ec.message() << "\n";
    return 2;
  }
  const bool set = reports.size() > 1;
  Status st = set ? run::write_sweep_set(reports, seeds, out.string()) : run::write_sweep_outputs(reports[0], out.string());
  if (!st.ok()) {
    *o.log << "orthosonar batch merge: " << st.error().message << "\n";
    return 2;
  }
  for (size_t k = 0; k < reports.size(); ++k) {
    if (!reference_task[k]) continue;
    const fs::path dir = set ? out / run::sweep_set_dir(reports[k].scene, seeds[k]) : out;
    if (Status s = copy_tree(fs::path(result_dir(plan, *reference_task[k])) / "reference", dir); !s.ok()) {
      *o.log << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
    if (Status s = write_sweep_report(dir.string(), "orthosonar sweep: " + reports[k].scene); !s.ok()) {
      *o.log << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
  }
  *o.out << (set ? run::seeds_markdown(reports, seeds) : run::sweep_tables_markdown(reports[0]));
  *o.log << "batch merge: " << plan.tasks.size() << " tasks merged into " << out.string() << "\n";
  return 0;
}

// verify / golden: a summary (markdown + JSON) and JUnit XML, one test case per task.
int merge_verdicts(const Plan& plan, const Gathered& g, const fs::path& out, const MergeOptions& o) {
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    *o.log << "orthosonar batch merge: cannot create '" << out.string() << "': " << ec.message() << "\n";
    return 2;
  }
  const std::string suite = "orthosonar " + plan.kind;
  size_t failures = 0, errors = 0;
  double total_s = 0.0;
  std::ostringstream cases, md;
  json summary = {{"kind", plan.kind}, {"tasks", json::array()}};
  const json cut_tasks = note_cut_tasks(plan, g, o);
  md << "# " << suite << "\n\n| Task | Result |\n|---|---|\n";
  for (const auto& t : plan.tasks) {
    const auto& r = g.results[t.index];
    const double time_s = r ? r->value("wall_s", 0.0) : 0.0;
    total_s += time_s;
    char tbuf[32];
    std::snprintf(tbuf, sizeof tbuf, "%.3f", time_s);
    cases << "    <testcase classname=\"" << xml_escape("orthosonar." + plan.kind) << "\" name=\"" << xml_escape(t.name)
          << "\" time=\"" << tbuf << "\"";
    std::string verdict;
    if (!r) {
      ++errors;
      const TaskStatus st = task_status(plan, t, false);
      const std::string msg = state_name(st.state) + ": " + st.detail;
      cases << ">\n      <error message=\"" << xml_escape("no result: " + msg) << "\" type=\"missing\">"
            << xml_escape("log: " + log_path(plan, t.index)) << "</error>\n    </testcase>\n";
      verdict = "MISSING (" + msg + ")";
    } else if (!r->value("passed", false)) {
      ++failures;
      const std::string message = r->value("message", std::string());
      const std::string first_line = message.substr(0, message.find('\n'));
      cases << ">\n      <failure message=\"" << xml_escape(first_line) << "\" type=\""
            << (plan.kind == "verify" ? "digest" : "golden") << "\">" << xml_escape(message) << "</failure>\n    </testcase>\n";
      verdict = plan.kind == "verify" ? "DIFFERENT: " + first_line : "FAIL";
    } else {
      cases << "/>\n";
      verdict = plan.kind == "verify" ? "identical: " + r->value("got", std::string()) : "PASS";
    }
    if (r && r->contains("input_cut")) verdict += " (INPUT CUT SHORT)";
    md << "| " << t.name << " | " << verdict << " |\n";
    summary["tasks"].push_back({{"index", t.index}, {"name", t.name}, {"verdict", verdict},
                                {"passed", r && r->value("passed", false)}});
  }
  char tot[32];
  std::snprintf(tot, sizeof tot, "%.3f", total_s);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"" << xml_escape(suite) << "\" tests=\""
      << plan.tasks.size() << "\" failures=\"" << failures << "\" errors=\"" << errors << "\" time=\"" << tot << "\">\n"
      << "  <testsuite name=\"" << xml_escape(suite) << "\" tests=\"" << plan.tasks.size() << "\" failures=\"" << failures
      << "\" errors=\"" << errors << "\" skipped=\"0\" time=\"" << tot << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  const size_t passed = plan.tasks.size() - failures - errors;
  md << "\n" << passed << " of " << plan.tasks.size() << " passed, " << failures << " failed, " << errors << " missing.\n";
  summary["passed"] = passed;
  summary["failed"] = failures;
  summary["missing"] = errors;
  summary["input_cut_tasks"] = cut_tasks;
  if (!cut_tasks.empty()) md << cut_tasks.size() << " task(s) ran on an input cut short: see summary.json input_cut_tasks.\n";
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"junit.xml", xml.str()},
                                   {"summary.md", md.str()}, {"summary.json", summary.dump(2) + "\n"}})
    if (Status s = write_text(out / name, text); !s.ok()) {
      *o.log << "orthosonar batch merge: " << s.error().message << "\n";
      return 2;
    }
  *o.out << md.str();
  *o.log << "batch merge: JUnit XML " << (out / "junit.xml").string() << "\n";
  if (errors) {
    report_problems(plan, g, *o.log);
    return 2;
  }
  return failures ? 1 : 0;
}

}  // namespace

int merge(const Plan& plan, const MergeOptions& options) {
  const fs::path out = options.out_dir.empty() ? fs::path(plan.dir) / "merged" : fs::path(options.out_dir);
  const Gathered g = gather(plan);
  return plan.kind == "sweep" ? merge_sweep(plan, g, out, options) : merge_verdicts(plan, g, out, options);
}

}  // namespace orthosonar::batch
