#pragma once
// The seam between orthosonar_inference and libtorch (docs/ARCHITECTURE.md, "libtorch, loaded
// on demand"). libtorch's start-up (its operator registry, ~290 shared libraries) costs about
// a second; most subcommands (simulate, replay, run without the inference systems) never use
// it. So libtorch is linked only into a shared module, liborthosonar_torch.so
// (torch/classifier_torch.cpp), which classifier.cpp loads with dlopen the first time a
// classifier or a torch setting is needed. This header is the module's whole interface:
// plain C++ types, the same compiler and standard library on both sides (one build).
#include <cstdint>
#include <string>
#include <vector>

#include "core/inference/classifier.hpp"

namespace orthosonar::inference::torch_backend {

// One network; created and destroyed inside the module (the module is never unloaded).
// Default visibility: the module is built with hidden symbols, but this type's typeinfo and
// vtable must be the same on both sides (UBSan's vptr check, dynamic_cast).
class __attribute__((visibility("default"))) Model {
 public:
  virtual ~Model() = default;
  virtual const ClassifierConfig& config() const = 0;
  virtual const std::vector<SemanticClass>& classes() const = 0;
  virtual std::string serialize() const = 0;
  virtual std::vector<Prediction> classify(const std::vector<cv::Mat>& crops, uint64_t seed) const = 0;
  virtual std::vector<std::vector<float>> mc_probabilities(const cv::Mat& crop, uint64_t seed) const = 0;
  virtual std::vector<std::vector<float>> probabilities(const std::vector<cv::Mat>& crops) const = 0;
  virtual double train(const std::vector<LabelledCrop>& data, const TrainConfig& config, uint64_t seed) = 0;
};

// Bumped whenever Api or Model change; the loader refuses a module built with another.
constexpr int kAbiVersion = 1;

struct Api {
  int abi_version = 0;
  size_t config_size = 0;  // sizeof(ClassifierConfig) in the module: a second ABI check
  void (*pin_onednn)() = nullptr;  // dnnl_set_max_cpu_isa(SSE4.1), before oneDNN's first primitive
  InferenceRuntime::Status (*status)() = nullptr;
  void (*set_threads)(int threads) = nullptr;
  void (*manual_seed)(uint64_t seed) = nullptr;
  Model* (*create)(const ClassifierConfig& config, const std::vector<SemanticClass>& classes, uint64_t init_seed) = nullptr;
  // nullptr with *error set when the bytes are not a model.
  Model* (*deserialize)(const std::string& bytes, const ClassifierConfig& runtime, std::string* error) = nullptr;
};

// The symbol the module exports (extern "C", looked up with dlsym).
inline constexpr const char* kEntryPoint = "orthosonar_torch_api";
using EntryPoint = const Api* (*)();

}  // namespace orthosonar::inference::torch_backend
