#include <catch2/catch.hpp>
#include <cmath>

#include "hal/drivers/dvl_protocols.hpp"
#include "hal/drivers/line_framer.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

TEST_CASE("line framer splits and bounds lines", "[hal]") {
  LineFramer f(16);
  const std::string s = "abc\r\n0123456789abcdefXYZ\nok\n";
  f.push(as_bytes(s));
  CHECK(*f.pop() == "abc");
  CHECK(*f.pop() == "ok");
  CHECK_FALSE(f.pop());
  CHECK(f.overlong() == 1);
}
