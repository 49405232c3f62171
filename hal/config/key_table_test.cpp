// The key-table machinery on its own: ranges, parity, the two wordings, aliases, checks, and
// the pose text's faults.
#include "hal/config/key_table.hpp"

#include <catch2/catch.hpp>

#include "hal/config/pose6.hpp"

namespace orthosonar::config {
namespace {

Status apply_text(const KeyTables& k, const std::string& yaml, const Table& t) { return k.apply(YAML::Load(yaml), t, ""); }

TEST_CASE("key tables read in range, reject out of range in each wording", "[config]") {
  const KeyTables plain({.prefix = "a: ", .integer_range_colon = true, .pose_names_part = true});
  const KeyTables named({.prefix = "b: ", .choice_names_value = true});
  double x = 0.5;
  int n = 3;
  bool flag = false;
  std::string picked;
  SE3 pose = SE3::Identity();
  auto table = [&](const KeyTables& k) {
    return Table{{"x", k.real(x, 0.0, 1.0, true)},
                 {"n", k.integer(n, 1, 9, Parity::kOdd)},
                 {"flag", k.boolean(flag)},
                 {"pick", k.choice("p, q", [&](const std::string& s) {
                    if (s != "p" && s != "q") return false;
                    picked = s;
                    return true;
                  })},
                 {"pose", k.pose(pose)},
                 {"sub", k.nested([&] { return Table{{"x", k.real(x, 0.0, 1.0)}}; })}};
  };
  REQUIRE(apply_text(plain, "{x: 0.25, n: 7, flag: true, pick: q, pose: '1 2 3 0 0 0.5', sub: {x: 1}}", table(plain)).ok());
  CHECK(x == 1.0);
  CHECK(n == 7);
  CHECK(flag);
  CHECK(picked == "q");
  CHECK(pose.translation().isApprox(Vec3(1, 2, 3)));

  CHECK(apply_text(plain, "{x: 0}", table(plain)).error().message == "a: 'x' = 0 is outside its valid range (0, 1]");
  CHECK(apply_text(named, "{x: 0}", table(named)).error().message == "b: 'x' = 0 is outside its valid range (0, 1]");
  CHECK(apply_text(plain, "{n: 4}", table(plain)).error().message ==
        "a: 'n' = 4 is outside its valid range: integer in [1, 9], odd");
  CHECK(apply_text(named, "{n: 4}", table(named)).error().message ==
        "b: 'n' = 4 is outside its valid range integer in [1, 9], odd");
  CHECK(apply_text(plain, "{pick: r}", table(plain)).error().message == "a: 'pick' must be one of p, q");
  CHECK(apply_text(named, "{pick: r}", table(named)).error().message == "b: 'pick' is 'r', expected one of p, q");
  CHECK(apply_text(plain, "{pose: '0 0 0 0 7 0'}", table(plain)).error().message.find("a: 'pose' angle is outside") == 0);
  CHECK(apply_text(plain, "{pose: '0 200 0 0 0 0'}", table(plain)).error().message.find("a: 'pose' translation is outside") == 0);
  CHECK(apply_text(named, "{pose: '0 200 0 0 0 0'}", table(named)).error().message.find("b: 'pose' is outside") == 0);
  CHECK(apply_text(named, "{sub: {y: 1}}", table(named)).error().message == "b: unknown key 'sub.y'");
  CHECK(apply_text(named, "{flag: maybe}", table(named)).error().message == "b: 'flag' must be true or false");
  CHECK(apply_text(named, "[1]", table(named)).error().message == "b: '<root>' must be a map");
}

TEST_CASE("key tables set aliases together, check values set in code, list ranges", "[config]") {
  const KeyTables k({.prefix = "c: "});
  int a = 4, b = 4;
  const Table t = {{"both", k.integer<int>({&a, &b}, 2, 8, Parity::kEven, false)}, {"a", k.integer(a, 2, 8, Parity::kEven)}};
  REQUIRE(k.apply(YAML::Load("{both: 6}"), t, "").ok());
  CHECK((a == 6 && b == 6));
  CHECK(KeyTables::check(t).ok());
  a = 5;
  CHECK(KeyTables::check(t).error().message == "c: 'a' = 5 is outside its valid range integer in [2, 8], even");
  const auto r = KeyTables::ranges(t);
  REQUIRE(r.size() == 2);
  CHECK((r[0].key == "a" && r[0].range == "integer in [2, 8], even" && r[0].bad_value == "1"));
  // Applying only the keys a caller selects (the simulator's order of precedence).
  a = 4;
  REQUIRE(k.apply(YAML::Load("{both: 8, a: 2}"), t, "", [](const std::string& key) { return key == "a"; }).ok());
  CHECK((a == 2 && b == 6));
}

TEST_CASE("pose text: six finite numbers, faults named, formatted and read back", "[config]") {
  CHECK(read_pose6("1 2 3 0.1 0.2 0.3").fault == Pose6Text::Fault::kNone);
  CHECK(read_pose6("1 2 3 0.1 0.2").fault == Pose6Text::Fault::kNotSixFiniteNumbers);
  CHECK(read_pose6("1 2 nan 0.1 0.2 0.3").fault == Pose6Text::Fault::kNotSixFiniteNumbers);
  const Pose6Text extra = read_pose6("1 2 3 0.1 0.2 0.3 x y");
  CHECK(extra.fault == Pose6Text::Fault::kTrailingText);
  CHECK(extra.rest == "x");
  CHECK(parse_pose6("1 2 3 0.1 0.2 0.3 4").error().message == "pose '1 2 3 0.1 0.2 0.3 4': trailing text '4'");
  const SE3 T = se3_from_xyz_rpy(0.1, -2.5, 3.0, 0.3, -0.2, 1.1);
  const auto back = parse_pose6(format_pose6(T));
  REQUIRE(back.ok());
  CHECK(back->isApprox(T, 1e-15));
  CHECK(format_pose6(*back).find("0.10000000000000001 -2.5 3 ") == 0);
}

}  // namespace
}  // namespace orthosonar::config
