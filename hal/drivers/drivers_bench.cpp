// Driver decode throughput: the real M1200d capture through the Oculus stream parser and
// SonarPing conversion, and a full-resolution synthetic M750d ping (512 beams x 600 ranges);
// VN-100 and DSP-1760 packet streams.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "hal/drivers/dsp1760.hpp"
#include "hal/drivers/oculus_stream.hpp"
#include "hal/drivers/rti_ensemble.hpp"
#include "hal/drivers/vn100.hpp"

using namespace orthosonar;
using namespace orthosonar::hal::drivers;

namespace {

// The capture is in the repository (testdata/oculus/, with its licence): found from
// ORTHOSONAR_SOURCE when set, else relative to this source file.
Bytes real_capture() {
  const char* s = std::getenv("ORTHOSONAR_SOURCE");
  const std::filesystem::path root = s != nullptr && *s != '\0' ? std::filesystem::path(s)
                                                                 : std::filesystem::path(__FILE__).parent_path() / ".." / "..";
  std::ifstream in(root / "testdata" / "oculus" / "m1200d_one_ping_8bit.raw", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Bytes full_ping() {
  SonarPing p;
  p.rows = 600;
  p.cols = 512;
  p.range_resolution_m = 0.05;
  for (int c = 0; c < 512; ++c) p.bearings_rad.push_back(-1.13 + 2.26 * c / 511.0);
  p.image.resize(600u * 512u);
  for (size_t i = 0; i < p.image.size(); ++i) p.image[i] = static_cast<uint8_t>(i * 31);
  return oculus::encode_ping_result(oculus::ping_result_from(p, 2, 1));
}

void decode(benchmark::State& state, const Bytes& wire) {
  if (wire.empty()) {
    state.SkipWithError("no input");
    return;
  }
  for (auto _ : state) {
    oculus::StreamParser parser;
    parser.push(wire);
    auto m = parser.pop();
    auto s = oculus::to_sonar_ping(std::get<oculus::PingResult>(*m), SonarMount::kHorizontal, kPartM750d, Time());
    benchmark::DoNotOptimize(s);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(wire.size()));
}

void BM_OculusDecodeRealCapture(benchmark::State& state) { decode(state, real_capture()); }
void BM_OculusDecodeFullPing512x600(benchmark::State& state) { decode(state, full_ping()); }

void BM_Vn100Decode(benchmark::State& state) {
  ImuReading r;
  const Bytes one = vn100::encode_packet(vn100::message_from(r, Quat::Identity()));
  Bytes wire;
  for (int i = 0; i < 100; ++i) wire.insert(wire.end(), one.begin(), one.end());
  for (auto _ : state) {
    vn100::StreamParser p;
    p.push(wire);
    int n = 0;
    while (auto m = p.pop()) n += vn100::to_imu_reading(*m, Quat::Identity(), Time()).ok();
    benchmark::DoNotOptimize(n);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * 100);
}

// 64 KiB of DSP-1760 packets (one read of a busy serial port) framed, CRC-checked and
// converted to GyroReadings: bytes per second is the decoding speed (target >= 200 MB/s).
void BM_Dsp1760Decode(benchmark::State& state) {
  Bytes wire;
  for (unsigned i = 0; wire.size() + dsp1760::kPacketBytes <= dsp1760::StreamParser::kMaxBuffered; ++i) {
    dsp1760::Packet p;
    p.xyz = {1e-5f * static_cast<float>(i % 97), -2e-6f, 3e-7f};
    p.status = dsp1760::kStatusXyz;
    p.sequence = static_cast<uint8_t>(i % dsp1760::kSequenceModulo);
    p.temperature_raw = 2500;
    const Bytes b = dsp1760::encode_packet(p);
    wire.insert(wire.end(), b.begin(), b.end());
  }
  const dsp1760::Config c;
  for (auto _ : state) {
    dsp1760::StreamParser parser;
    parser.push(wire);
    double sum = 0;
    while (auto p = parser.pop()) sum += dsp1760::to_gyro_reading(*p, c, Time()).value_G.x();
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(wire.size()));
}

// Rowe RTI ensembles as a DVL streams them (256 KiB), framed, CRC-checked, decoded and
// converted to DvlReadings: bytes per second is the decoding speed (target >= 200 MB/s).
// Arg 0: ensemble data, ancillary and bottom track (~630 B each); arg 30: plus beam velocity,
// amplitude and correlation profiles of 30 bins x 4 beams, skipped by their declared size.
void BM_RtiEnsembleDecode(benchmark::State& state) {
  const auto bins = static_cast<int32_t>(state.range(0));
  Bytes wire;
  for (uint32_t n = 1; wire.size() < 256 * 1024; ++n) {
    DvlReading r;
    r.velocity_V_mps = Vec3(0.01 * (n % 50), -0.2, 0.05);
    r.altitude_m = 3.5;
    const rti::Ensemble e = rti::ensemble_from(r, Quat::Identity(), n, Time::from_ms(200 * int64_t{n}));
    std::vector<Bytes> sets{rti::encode(*e.ensemble_data),
                            rti::encode_data_set(rti::kAncillaryName, rti::kTypeFloat, 19, 1, Bytes(19 * 4, 0))};
    if (bins > 0)
      for (const char* name : {"E000001", "E000004", "E000005"})
        sets.push_back(rti::encode_data_set(name, rti::kTypeFloat, bins, 4, Bytes(static_cast<size_t>(bins) * 16, 0x3f)));
    sets.push_back(rti::encode(*e.bottom_track));
    const Bytes one = rti::encode_ensemble(n, sets);
    wire.insert(wire.end(), one.begin(), one.end());
  }
  for (auto _ : state) {
    rti::StreamParser parser;
    parser.push(wire);
    double sum = 0;
    while (auto e = parser.pop())
      if (auto r = rti::to_dvl_reading(*e, Quat::Identity(), Time())) sum += r->velocity_V_mps.x();
    benchmark::DoNotOptimize(sum);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(wire.size()));
}

}  // namespace

BENCHMARK(BM_OculusDecodeRealCapture);
BENCHMARK(BM_OculusDecodeFullPing512x600);
BENCHMARK(BM_Vn100Decode);
BENCHMARK(BM_RtiEnsembleDecode)->Arg(0)->Arg(30);
BENCHMARK(BM_Dsp1760Decode);
