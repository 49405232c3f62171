#include "core/inference/numeric_pins.hpp"

#include <dlfcn.h>

#include <Eigen/Core>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <string>
#include <system_error>

#include "core/inference/classifier.hpp"

namespace orthosonar::inference {
namespace {

// The thread controls of the BLAS libraries that have one, found through the dynamic
// linker: whichever BLAS the system's alternatives put behind libblas.so.3 (Ceres, CHOLMOD,
// libtorch and OpenCV all link it) is the one in the process.
struct BlasThreads {
  const char* library;
  const char* set;  // void set(int)
  const char* get;  // int get()
};
constexpr BlasThreads kBlasThreadControls[] = {
    {"OpenBLAS", "openblas_set_num_threads", "openblas_get_num_threads"},
    {"BLIS", "bli_thread_set_num_threads", "bli_thread_get_num_threads"},
    {"MKL", "MKL_Set_Num_Threads", "MKL_Get_Max_Threads"},
};

// The file that provides `symbol` in this process (symlinks resolved), or "none loaded".
std::string library_file(const char* symbol) {
  void* sym = ::dlsym(RTLD_DEFAULT, symbol);
  Dl_info info{};
  if (sym == nullptr || ::dladdr(sym, &info) == 0 || info.dli_fname == nullptr) return "none loaded";
  std::error_code ec;
  const auto real = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::string(info.dli_fname) : real.string();
}

NumericPin blas_pin(bool apply) {
  NumericPin p{"blas.threads", "1", "", false, ""};
  const std::string dgemm = "dgemm_ from " + library_file("dgemm_");
  for (const BlasThreads& c : kBlasThreadControls) {
    auto set = reinterpret_cast<void (*)(int)>(::dlsym(RTLD_DEFAULT, c.set));
    auto get = reinterpret_cast<int (*)()>(::dlsym(RTLD_DEFAULT, c.get));
    if (set == nullptr || get == nullptr) continue;
    if (apply) set(1);
    p.effective = std::to_string(get());
    p.ok = p.effective == "1";
    // Appended, not a `+` chain: GCC 12 at -O3 reports a false -Wrestrict in those.
    p.note.assign(c.library);
    p.note.append(" ");
    p.note.append(library_file(c.set));
    p.note.append("; ");
    p.note.append(dgemm);
    return p;
  }
  // No thread control: reference BLAS or serial ATLAS (Debian's libblas.so.3 alternatives
  // other than OpenBLAS/BLIS/MKL are single-threaded).
  p.effective = "1";
  p.ok = true;
  p.note.assign("serial BLAS without thread control; ");
  p.note.append(dgemm);
  return p;
}

NumericPin opencv_dispatch_pin() {
  // Off: cv::checkHardwareSupport() answers false for every feature, so OpenCV's runtime
  // dispatch (CV_CPU_DISPATCH: AVX2/AVX-512 variants of resize, warpAffine, arithmetic) and
  // IPP are not used; only the baseline SIMD compiled into the library runs, on every CPU.
  const bool avx2 = cv::checkHardwareSupport(CV_CPU_AVX2);
  const bool optimized = cv::useOptimized();
  NumericPin p{"opencv.cpu_dispatch", "off", "", false, ""};
  p.effective = optimized || avx2 ? std::string("on (avx2 ") + (avx2 ? "yes" : "no") + ")" : "off";
  p.ok = !optimized && !avx2;
  p.note = "cv::setUseOptimized(false); build baseline: " + cv::getCPUFeaturesLine();
  return p;
}

}  // namespace

std::vector<NumericPin> numeric_pins_report() {
  std::vector<NumericPin> pins;
  const InferenceRuntime::Status t = InferenceRuntime::status();
  pins.push_back({"torch.aten_cpu_capability", "DEFAULT", t.aten_capability, t.aten_capability == "DEFAULT",
                  "ATEN_CPU_CAPABILITY=default before the first operator"});
  pins.push_back({"torch.onednn_max_isa", "sse41", t.onednn_isa, t.onednn_isa == "sse41" || t.onednn_isa == "absent",
                  "dnnl_set_max_cpu_isa(sse41) before the first primitive"});
  pins.push_back({"torch.intra_op_threads", "1", std::to_string(t.intra_op_threads), t.intra_op_threads == 1,
                  "torch::set_num_threads"});
  pins.push_back({"torch.inter_op_threads", "1", std::to_string(t.inter_op_threads), t.inter_op_threads == 1,
                  "torch::set_num_interop_threads"});
  pins.push_back(blas_pin(false));
  pins.push_back({"opencv.threads", "1", std::to_string(cv::getNumThreads()), cv::getNumThreads() == 1,
                  "cv::setNumThreads(1)"});
  pins.push_back(opencv_dispatch_pin());
  pins.push_back({"eigen.threads", "1", std::to_string(Eigen::nbThreads()), Eigen::nbThreads() == 1,
                  "Eigen::setNbThreads(1) (Eigen parallelises only under OpenMP)"});
  return pins;
}

void apply_numeric_pins() {
  InferenceRuntime::pin_cpu_kernels();
  InferenceRuntime::set_threads(1);
  blas_pin(true);
  cv::setNumThreads(1);
  cv::setUseOptimized(false);
  Eigen::setNbThreads(1);
}

}  // namespace orthosonar::inference
