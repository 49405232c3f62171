// The key-table machinery: the entries every option file uses (real, integer, boolean,
// choice, pose, nested map) and the walk that applies, checks and lists a table.
#include "hal/config/key_table.hpp"

#include <cmath>
#include <sstream>

#include "hal/config/pose6.hpp"

namespace orthosonar::config {

std::string number_text(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

Status KeyTables::integer_out_of_range(const Wording& w, const std::string& where, const std::string& value,
                                       const std::string& range) {
  return Error{w.prefix + "'" + where + "' = " + value + " is outside its valid range" +
               (w.integer_range_colon ? ": " : " ") + range};
}

Entry KeyTables::real(std::vector<double*> targets, double lo, double hi, bool lo_open, bool hi_open,
                      bool checked) const {
  Entry e;
  e.range = std::string(lo_open ? "(" : "[") + number_text(lo) + ", " + number_text(hi) + (hi_open ? ")" : "]");
  e.bad = lo_open ? number_text(lo) : number_text(lo - 1.0);
  auto in_range = [lo, hi, lo_open, hi_open](double v) {
    return std::isfinite(v) && (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  };
  auto outside = [w = w_](const std::string& where, double v, const std::string& range) -> Status {
    return Error{w.prefix + "'" + where + "' = " + number_text(v) + " is outside its valid range " + range};
  };
  e.read = [w = w_, targets, in_range, outside, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      return Error{w.prefix + "'" + where + "' must be a number in " + range};
    }
    if (!in_range(v)) return outside(where, v, range);
    for (double* t : targets) *t = v;
    return {};
  };
  if (checked)
    e.check = [t = targets.front(), in_range, outside, range = e.range](const std::string& where) -> Status {
      if (!in_range(*t)) return outside(where, *t, range);
      return {};
    };
  return e;
}

Entry KeyTables::boolean(bool& target) const {
  Entry e;
  e.range = "true or false";
  e.bad = "maybe";
  e.read = [w = w_, &target](const YAML::Node& n, const std::string& where) -> Status {
    try {
      target = n.as<bool>();
    } catch (const YAML::Exception&) {
      return Error{w.prefix + "'" + where + "' must be true or false"};
    }
    return {};
  };
  return e;
}

Entry KeyTables::choice(std::string range, std::function<bool(const std::string&)> set) const {
  Entry e;
  e.range = "one of: " + range;
  e.bad = "none_of_these";
  e.read = [w = w_, set, range](const YAML::Node& n, const std::string& where) -> Status {
    const auto text = n.IsScalar() ? n.Scalar() : std::string();
    if (set(text)) return {};
    if (w.choice_names_value) return Error{w.prefix + "'" + where + "' is '" + text + "', expected one of " + range};
    return Error{w.prefix + "'" + where + "' must be one of " + range};
  };
  return e;
}

namespace {

constexpr double kPoseMaxM = 100.0, kPoseMaxRad = 6.2832;

// The first of the six values out of its bound (-1: none).
int pose_outside(const std::array<double, 6>& v) {
  for (int i = 0; i < 6; ++i)
    if (!std::isfinite(v[static_cast<size_t>(i)]) || std::abs(v[static_cast<size_t>(i)]) > (i < 3 ? kPoseMaxM : kPoseMaxRad))
      return i;
  return -1;
}

}  // namespace

Entry KeyTables::pose(SE3& target) const {
  Entry e;
  e.range = "\"x y z roll pitch yaw\": |x|,|y|,|z| <= 100 m, angles in [-6.2832, 6.2832] rad";
  e.bad = "\"0 0 0 0 0\"";
  auto outside = [w = w_](const std::string& where, int which, const std::string& range) -> Status {
    const char* part = !w.pose_names_part ? "' is outside " : which < 3 ? "' translation is outside " : "' angle is outside ";
    return Error{w.prefix + "'" + where + part + range};
  };
  e.read = [w = w_, &target, outside, range = e.range](const YAML::Node& n, const std::string& where) -> Status {
    const Pose6Text p = read_pose6(n.IsScalar() ? n.Scalar() : std::string());
    if (p.fault == Pose6Text::Fault::kNotSixFiniteNumbers) return Error{w.prefix + "'" + where + "' must be " + range};
    if (p.fault == Pose6Text::Fault::kTrailingText)
      return Error{w.prefix + "'" + where + "' has more than six numbers; must be " + range};
    if (const int i = pose_outside(p.v); i >= 0) return outside(where, i, range);
    target = pose6_se3(p.v);
    return {};
  };
  e.check = [&target, outside, range = e.range](const std::string& where) -> Status {
    const Vec3 t = target.translation();
    const Vec3 rpy = rpy_from_rotation(target.rotation());
    const std::array<double, 6> v = {t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z()};
    const int i = pose_outside(v);
    if (!target.matrix().allFinite() || i >= 0) return outside(where, i < 0 ? 0 : i, range);
    return {};
  };
  return e;
}

Entry KeyTables::nested(std::function<Table()> make) const {
  Entry e;
  e.children = make;
  e.read = [self = *this, make](const YAML::Node& n, const std::string& where) { return self.apply(n, make(), where); };
  return e;
}

Status KeyTables::apply(const YAML::Node& node, const Table& table, const std::string& prefix,
                        const std::function<bool(const std::string&)>& now) const {
  const std::string name = prefix.empty() ? std::string("<root>") : prefix;
  if (!node.IsMap()) return error("'" + name + "' must be a map");
  for (const auto& kv : node) {
    if (!kv.first.IsScalar())
      return error("a key in '" + name + "' is not a plain name (a sequence, a map or '?' with no key)");
    const std::string key = kv.first.as<std::string>();
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    const auto it = table.find(key);
    if (it == table.end()) return error("unknown key '" + where + "'");
    if (now && !now(key)) continue;
    if (Status s = it->second.read(kv.second, where); !s.ok()) return s;
  }
  return {};
}

Status KeyTables::check(const Table& table, const std::string& prefix) {
  for (const auto& [key, e] : table) {
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    if (e.children) {
      if (Status s = check(e.children(), where); !s.ok()) return s;
    } else if (e.check) {
      if (Status s = e.check(where); !s.ok()) return s;
    }
  }
  return {};
}

namespace {

void list_ranges(const Table& t, const std::string& prefix, std::vector<KeyRange>& out) {
  for (const auto& [key, e] : t) {
    const std::string where = prefix.empty() ? key : prefix + "." + key;
    if (e.children) list_ranges(e.children(), where, out);
    else out.push_back({where, e.range, e.bad});
  }
}

}  // namespace

std::vector<KeyRange> KeyTables::ranges(const Table& table) {
  std::vector<KeyRange> out;
  list_ranges(table, "", out);
  return out;
}

}  // namespace orthosonar::config
