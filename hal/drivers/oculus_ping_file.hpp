#pragma once
// A file holding one raw Oculus ping result as the sonar sent it (e.g.
// testdata/oculus/m1200d_one_ping_8bit.raw): read, decode, convert to a SonarPing.
#include <string>

#include "core/events.hpp"
#include "core/result.hpp"
#include "hal/drivers/oculus_protocol.hpp"
#include "hal/drivers/oculus_stream.hpp"

namespace orthosonar::hal::drivers::oculus {

struct OculusPingFile {
  PingResult raw;
  SonarPing ping;  // mounted as the vertical sonar (the M1200d's place)
};

// Errors name the option (e.g. "--real-ping") and the path.
Result<OculusPingFile> read_oculus_ping_file(const std::string& path, const std::string& option);

}  // namespace orthosonar::hal::drivers::oculus
