// The classifier's API on this side of the libtorch seam (torch_backend.hpp): it loads
// liborthosonar_torch.so the first time a network or a torch setting is needed, and keeps
// the process-wide settings asked for before then (pins, threads) to apply at load, in the
// order libtorch needs them. Nothing here includes or links libtorch.
#include "core/inference/classifier.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "core/inference/torch_backend.hpp"
#include "core/random.hpp"

namespace orthosonar::inference {
namespace {

using torch_backend::Api;

#ifndef ORTHOSONAR_TORCH_MODULE_BUILD
#define ORTHOSONAR_TORCH_MODULE_BUILD ""
#endif
#ifndef ORTHOSONAR_TORCH_MODULE_INSTALL
#define ORTHOSONAR_TORCH_MODULE_INSTALL ""
#endif
constexpr const char* kModuleName = "liborthosonar_torch.so";

// Settings asked for before the module was loaded; applied by load(), then forwarded.
std::mutex g_mutex;
bool g_pin_requested = false;
int g_threads_requested = 0;
std::atomic<const Api*> g_api{nullptr};

// Where the module may be, in order: $ORTHOSONAR_TORCH_MODULE (only that, when set); beside
// an installed executable (<prefix>/bin/../lib/orthosonar/); this build tree; the configured
// install prefix.
std::vector<std::string> candidates() {
  if (const char* env = std::getenv("ORTHOSONAR_TORCH_MODULE"); env != nullptr && *env != '\0') return {env};
  std::vector<std::string> out;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back((exe.parent_path().parent_path() / "lib" / "orthosonar" / kModuleName).string());
  for (const char* p : {ORTHOSONAR_TORCH_MODULE_BUILD, ORTHOSONAR_TORCH_MODULE_INSTALL})
    if (*p != '\0') out.emplace_back(p);
  return out;
}

// Caller holds g_mutex.
const Api* load_locked() {
  if (const Api* api = g_api.load()) return api;
  std::string tried;
  for (const std::string& path : candidates()) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += "\n  " + path + ": not found";
      continue;
    }
    // RTLD_GLOBAL: libtorch's own libraries (oneDNN, BLAS) join the global scope, where the
    // numeric pins find their controls with dlsym(RTLD_DEFAULT, ...).
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (handle == nullptr) {
      const char* why = ::dlerror();
      tried += "\n  " + path + ": " + (why ? why : "dlopen failed");
      continue;
    }
    auto entry = reinterpret_cast<torch_backend::EntryPoint>(::dlsym(handle, torch_backend::kEntryPoint));
    const Api* api = entry ? entry() : nullptr;
    if (api == nullptr || api->abi_version != torch_backend::kAbiVersion || api->config_size != sizeof(ClassifierConfig)) {
      tried += "\n  " + path + ": not a module of this build (entry point or ABI version differs)";
      continue;  // never dlclose: a half-initialised libtorch is not safe to unload
    }
    if (g_pin_requested) api->pin_onednn();
    if (g_threads_requested > 0) api->set_threads(g_threads_requested);
    g_api.store(api);
    return api;
  }
  throw std::runtime_error("cannot load the classifier's libtorch module " + std::string(kModuleName) +
                           " (set ORTHOSONAR_TORCH_MODULE to its path); tried:" + tried);
}

const Api& backend() {
  if (const Api* api = g_api.load()) return *api;
  std::lock_guard lock(g_mutex);
  return *load_locked();
}

const Api* loaded() { return g_api.load(); }

}  // namespace

void InferenceRuntime::pin_cpu_kernels() {
  // ATen computes its capability once, at the first dispatch, from this variable; an
  // existing value is overridden (the pin is the pin).
  ::setenv("ATEN_CPU_CAPABILITY", "default", 1);
  std::lock_guard lock(g_mutex);
  g_pin_requested = true;
  if (const Api* api = loaded()) api->pin_onednn();
}

InferenceRuntime::Status InferenceRuntime::status() { return backend().status(); }

void InferenceRuntime::set_threads(int threads) {
  std::lock_guard lock(g_mutex);
  g_threads_requested = std::max(1, threads);
  if (const Api* api = loaded()) api->set_threads(g_threads_requested);
}

void InferenceRuntime::configure(int threads, uint64_t seed) {
  pin_cpu_kernels();
  set_threads(threads);
  backend().manual_seed(seed);
}

struct Classifier::Impl {
  std::unique_ptr<torch_backend::Model> model;
};

Classifier::Classifier(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Classifier::Classifier(const ClassifierConfig& config, std::vector<SemanticClass> classes, uint64_t init_seed)
    : impl_(std::make_unique<Impl>()) {
  impl_->model.reset(backend().create(config, classes, init_seed));
}
Classifier::~Classifier() = default;
Classifier::Classifier(Classifier&&) noexcept = default;
Classifier& Classifier::operator=(Classifier&&) noexcept = default;

const ClassifierConfig& Classifier::config() const { return impl_->model->config(); }
const std::vector<SemanticClass>& Classifier::classes() const { return impl_->model->classes(); }
std::string Classifier::serialize() const { return impl_->model->serialize(); }

Result<Classifier> Classifier::deserialize(const std::string& bytes, const ClassifierConfig& runtime) {
  const Api* api = nullptr;
  try {
    api = &backend();
  } catch (const std::runtime_error& e) {
    return Error{e.what()};
  }
  std::string error;
  torch_backend::Model* m = api->deserialize(bytes, runtime, &error);
  if (m == nullptr) return Error{error};
  auto impl = std::make_unique<Impl>();
  impl->model.reset(m);
  return Classifier(std::move(impl));
}

std::vector<Prediction> Classifier::classify(const std::vector<cv::Mat>& crops, uint64_t seed) const {
  return impl_->model->classify(crops, seed);
}
std::vector<std::vector<float>> Classifier::mc_probabilities(const cv::Mat& crop, uint64_t seed) const {
  return impl_->model->mc_probabilities(crop, seed);
}
std::vector<std::vector<float>> Classifier::probabilities(const std::vector<cv::Mat>& crops) const {
  return impl_->model->probabilities(crops);
}
double Classifier::train(const std::vector<LabelledCrop>& data, const TrainConfig& config, uint64_t seed) {
  return impl_->model->train(data, config, seed);
}

std::vector<PerClassAccuracy> Classifier::evaluate(const std::vector<LabelledCrop>& data, uint64_t seed) const {
  std::vector<PerClassAccuracy> acc(classes().size());
  for (size_t c = 0; c < acc.size(); ++c) acc[c].semantic = classes()[c];
  constexpr size_t kChunk = 64;
  for (size_t start = 0; start < data.size(); start += kChunk) {
    const size_t end = std::min(data.size(), start + kChunk);
    std::vector<cv::Mat> crops;
    for (size_t k = start; k < end; ++k) crops.push_back(data[k].crop);
    const auto probs = probabilities(crops);
    const auto preds = classify(crops, derive_seed(seed, start));
    for (size_t k = start; k < end; ++k) {
      const size_t label = static_cast<size_t>(data[k].label);
      if (label >= acc.size()) continue;
      PerClassAccuracy& a = acc[label];
      ++a.samples;
      const auto& p = probs[k - start];
      const size_t argmax = static_cast<size_t>(std::max_element(p.begin(), p.end()) - p.begin());
      if (argmax == label) ++a.correct;
      if (preds[k - start].known) {
        ++a.accepted;
        if (static_cast<size_t>(preds[k - start].class_index) == label) ++a.accepted_correct;
      }
    }
  }
  return acc;
}

}  // namespace orthosonar::inference
