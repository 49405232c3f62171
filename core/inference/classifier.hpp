#pragma once
// The object classifier of SPEC §8 / paper §VI-A: a CNN on 40x40 grayscale crops with two
// convolutional layers and dropout, evaluated with Monte-Carlo dropout.
//
//   conv 3x3 (1 -> c1) + ReLU + maxpool 2  ->  conv 3x3 (c1 -> c2) + ReLU + maxpool 2
//   -> dropout -> linear (c2*10*10 -> hidden) + ReLU -> dropout -> linear (hidden -> classes)
//
// Monte-Carlo dropout: the convolutional trunk has no dropout, so it is evaluated once per
// crop; the head is then evaluated on a batch of mc_samples copies with independent dropout
// masks (one forward of the batch). This is exactly the m stochastic passes of the paper,
// without recomputing the deterministic part m times. A class is accepted when its mean
// softmax probability over the passes is > accept_probability, else the crop is "unknown".
//
// Randomness: weights are initialised and dropout masks drawn with orthosonar::Rng (never
// torch's global generator), from seeds the caller passes in: the same seed gives the
// same bits on every run. Torch is confined to classifier.cpp; no header includes it.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/mesh.hpp"
#include "core/result.hpp"

namespace orthosonar::inference {

// Process-wide torch settings, made explicit (STYLE.md: no hidden global state in a
// constructor). Call once at program start, before any Classifier is used:
//   InferenceRuntime::configure(1, seed);
// Pins torch's CPU kernels (pin_cpu_kernels), sets torch's intra- and inter-op thread
// counts to `threads` (1 for the determinism contract and the per-frame benchmark) and
// seeds torch's global generator (which this library does not draw from, but third-party
// code might).
class InferenceRuntime {
 public:
  static void configure(int threads, uint64_t seed);

  // Pins what libtorch would otherwise choose from the CPU (docs/ARCHITECTURE.md,
  // "Cross-machine determinism: pinned numerics"): ATen's kernel capability
  // (ATEN_CPU_CAPABILITY=default, read once at ATen's first dispatch) and oneDNN's maximum
  // ISA (SSE4.1, settable only before oneDNN's first primitive). Takes effect only before
  // the first torch operator runs; later calls change nothing (the report says so).
  // Idempotent; apply_numeric_pins() (numeric_pins.hpp) calls it.
  static void pin_cpu_kernels();

  // The effective torch settings, as libtorch reports them.
  struct Status {
    std::string aten_capability;  // "DEFAULT", "AVX2", "AVX512" (at::show_config)
    std::string onednn_isa;       // "sse41", "avx2", ... (dnnl_get_effective_cpu_isa), or "absent"
    int intra_op_threads = 0;
    int inter_op_threads = 0;
  };
  static Status status();

  // Torch's intra- and inter-op thread counts (the inter-op count can be set only once per
  // process, before inter-op work; later attempts are ignored).
  static void set_threads(int threads);
};

struct ClassifierConfig {
  int input_px = 40;         // crops are input_px x input_px, CV_32F in [0, 1]
  int conv1_channels = 8;
  int conv2_channels = 16;
  int hidden = 64;
  double dropout = 0.5;      // drop probability, in training and in MC inference
  int mc_samples = 20;       // stochastic passes per crop
  double accept_probability = 0.99;  // mean probability needed to accept a class
};

struct Prediction {
  bool known = false;                   // mean probability > accept_probability
  int class_index = -1;                 // argmax of the mean (also when unknown)
  SemanticClass semantic = SemanticClass::kNone;  // classes()[class_index] when known
  double mean_probability = 0.0;        // of class_index
  std::vector<float> mean_probabilities;  // per class
};

struct LabelledCrop {
  cv::Mat crop;      // input_px x input_px, CV_32F in [0, 1]
  int label = 0;     // index into the classifier's classes
};

struct TrainConfig {
  int epochs = 12;
  int batch = 32;
  double learning_rate = 2e-3;
  double weight_decay = 1e-4;
};

struct PerClassAccuracy {
  SemanticClass semantic = SemanticClass::kNone;
  size_t samples = 0;
  size_t correct = 0;     // argmax of the deterministic (mean-field) forward
  size_t accepted = 0;    // MC dropout accepted a class
  size_t accepted_correct = 0;
  double accuracy() const { return samples ? static_cast<double>(correct) / static_cast<double>(samples) : 0.0; }
};

class Classifier {
 public:
  // A fresh network with weights drawn from init_seed.
  Classifier(const ClassifierConfig& config, std::vector<SemanticClass> classes, uint64_t init_seed);
  ~Classifier();
  Classifier(Classifier&&) noexcept;
  Classifier& operator=(Classifier&&) noexcept;

  // The model as bytes (torch archive) and back. mc_samples and accept_probability are
  // runtime settings taken from `runtime`; the architecture comes from the bytes.
  std::string serialize() const;
  static Result<Classifier> deserialize(const std::string& bytes, const ClassifierConfig& runtime = {});

  const ClassifierConfig& config() const;
  const std::vector<SemanticClass>& classes() const;

  // MC-dropout classification of a batch of crops; `seed` fixes every dropout mask
  // (derive it from (mission seed, frame) so a frame's result never depends on history).
  std::vector<Prediction> classify(const std::vector<cv::Mat>& crops, uint64_t seed) const;
  // The individual MC passes of one crop: mc_samples rows of class probabilities.
  std::vector<std::vector<float>> mc_probabilities(const cv::Mat& crop, uint64_t seed) const;
  // Deterministic forward (dropout as its expectation): class probabilities per crop.
  std::vector<std::vector<float>> probabilities(const std::vector<cv::Mat>& crops) const;

  // Mini-batch Adam on cross-entropy; shuffling and dropout masks from `seed`. Returns the
  // mean training loss of the last epoch.
  double train(const std::vector<LabelledCrop>& data, const TrainConfig& config, uint64_t seed);
  // Accuracy per class on a labelled set (deterministic forward and MC acceptance).
  std::vector<PerClassAccuracy> evaluate(const std::vector<LabelledCrop>& data, uint64_t seed) const;

 private:
  struct Impl;
  explicit Classifier(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace orthosonar::inference
