// liborthosonar_torch.so: the classifier's network and torch's process settings, the only
// code of orthosonar that includes or links libtorch. Loaded on demand by classifier.cpp
// through torch_backend.hpp (docs/ARCHITECTURE.md, "libtorch, loaded on demand").
#include "core/inference/torch_backend.hpp"

#include <ATen/Version.h>
#include <dlfcn.h>
#include <torch/torch.h>

#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/random.hpp"

namespace orthosonar::inference {
namespace {

constexpr uint64_t kInitStream = 0x1417;
constexpr uint64_t kMcStream = 0x3c3c;
constexpr uint64_t kShuffleStream = 0x5a5a;
constexpr uint64_t kTrainDropoutStream = 0x7e7e;

torch::Tensor uniform_tensor(std::vector<int64_t> shape, double bound, Rng& rng) {
  int64_t n = 1;
  for (int64_t s : shape) n *= s;
  std::vector<float> v(static_cast<size_t>(n));
  for (float& x : v) x = static_cast<float>(rng.uniform(-bound, bound));
  return torch::from_blob(v.data(), shape, torch::kFloat32).clone();
}

// Inverted-dropout masks (0 or 1/(1-p)) for `rows` rows of `cols`, drawn from rng.
void fill_mask(float* out, int64_t rows, int64_t cols, double p, Rng& rng) {
  const float keep = static_cast<float>(1.0 / (1.0 - p));
  for (int64_t i = 0; i < rows * cols; ++i) out[i] = rng.uniform() < p ? 0.0f : keep;
}

// oneDNN's C API, reached through the dynamic linker (libtorch links libdnnl; its headers are
// not part of libtorch's). Values of dnnl_cpu_isa_t, stable since oneDNN 1.x.
constexpr int kDnnlIsaSse41 = 0x1;
using DnnlSetMaxIsa = int (*)(int);
using DnnlGetEffectiveIsa = int (*)();

std::string dnnl_isa_name(int isa) {
  switch (isa) {
    case 0x1: return "sse41";
    case 0x3: return "avx";
    case 0x7: return "avx2";
    case 0x27: return "avx512_core";
    default: {
      std::ostringstream os;
      os << "isa 0x" << std::hex << isa;
      return os.str();
    }
  }
}


void pin_onednn() {
  // Returns an error once oneDNN has dispatched (the ISA is then fixed); status() reports
  // what is in effect either way. (ATEN_CPU_CAPABILITY is set by the loader, before this
  // module is loaded.)
  if (auto set_max = reinterpret_cast<DnnlSetMaxIsa>(::dlsym(RTLD_DEFAULT, "dnnl_set_max_cpu_isa"))) {
    set_max(kDnnlIsaSse41);
  }
}

InferenceRuntime::Status status() {
  InferenceRuntime::Status st;
  // at::show_config() reports the capability ATen dispatches with (computing it now if no
  // operator ran yet, from ATEN_CPU_CAPABILITY), as "CPU capability usage: AVX2" (or "NO
  // AVX" for DEFAULT).
  const std::string config = at::show_config();
  const std::string key = "CPU capability usage: ";
  const auto at_key = config.find(key);
  if (at_key != std::string::npos) {
    const auto from = at_key + key.size();
    st.aten_capability = config.substr(from, config.find('\n', from) - from);
    if (st.aten_capability == "NO AVX") st.aten_capability = "DEFAULT";  // how 1.13 names DEFAULT
  } else {
    st.aten_capability = "unknown";
  }
  if (auto get = reinterpret_cast<DnnlGetEffectiveIsa>(::dlsym(RTLD_DEFAULT, "dnnl_get_effective_cpu_isa"))) {
    st.onednn_isa = dnnl_isa_name(get());
  } else {
    st.onednn_isa = "absent";
  }
  st.intra_op_threads = torch::get_num_threads();
  st.inter_op_threads = torch::get_num_interop_threads();
  return st;
}

void set_threads(int threads) {
  const int n = std::max(1, threads);
  torch::set_num_threads(n);
  if (torch::get_num_interop_threads() != n) {
    try {
      torch::set_num_interop_threads(n);  // may only be set once per process
    } catch (const c10::Error&) {
    }
  }
}

void manual_seed(uint64_t seed) { torch::manual_seed(seed); }

struct Net {
  ClassifierConfig cfg;
  std::vector<SemanticClass> classes;
  torch::Tensor w1, b1, w2, b2, w3, b3, w4, b4;

  int64_t side_after_pools() const { return cfg.input_px / 4; }
  int64_t features() const { return cfg.conv2_channels * side_after_pools() * side_after_pools(); }
  std::vector<torch::Tensor*> params() { return {&w1, &b1, &w2, &b2, &w3, &b3, &w4, &b4}; }
  std::vector<const torch::Tensor*> params() const { return {&w1, &b1, &w2, &b2, &w3, &b3, &w4, &b4}; }

  void init(uint64_t seed) {
    Rng rng(derive_seed(seed, kInitStream));
    const auto layer = [&](torch::Tensor& w, torch::Tensor& b, std::vector<int64_t> shape, int64_t fan_in) {
      const double bound = 1.0 / std::sqrt(static_cast<double>(fan_in));  // PyTorch's default
      w = uniform_tensor(shape, bound * std::sqrt(3.0), rng);
      b = uniform_tensor({shape[0]}, bound, rng);
    };
    const int64_t c1 = cfg.conv1_channels, c2 = cfg.conv2_channels, h = cfg.hidden;
    layer(w1, b1, {c1, 1, 3, 3}, 9);
    layer(w2, b2, {c2, c1, 3, 3}, c1 * 9);
    layer(w3, b3, {h, features()}, features());
    layer(w4, b4, {static_cast<int64_t>(classes.size()), h}, h);
  }

  torch::Tensor batch(const std::vector<cv::Mat>& crops) const {
    const int64_t px = cfg.input_px;
    std::vector<float> buf(crops.size() * static_cast<size_t>(px * px));
    for (size_t i = 0; i < crops.size(); ++i) {
      const cv::Mat& c = crops[i];
      for (int r = 0; r < px; ++r) {
        const float* row = c.ptr<float>(r);
        std::copy(row, row + px, buf.begin() + static_cast<std::ptrdiff_t>((static_cast<int64_t>(i) * px + r) * px));
      }
    }
    return torch::from_blob(buf.data(), {static_cast<int64_t>(crops.size()), 1, px, px}, torch::kFloat32).clone();
  }

  // The deterministic convolutional trunk: [N,1,px,px] -> [N, features].
  torch::Tensor trunk(const torch::Tensor& x) const {
    auto y = torch::max_pool2d(torch::relu(torch::conv2d(x, w1, b1, 1, 1)), 2);
    y = torch::max_pool2d(torch::relu(torch::conv2d(y, w2, b2, 1, 1)), 2);
    return y.reshape({x.size(0), features()});
  }

  // The head; masks are undefined tensors for the expectation (no dropout).
  torch::Tensor head(const torch::Tensor& f, const torch::Tensor& m1, const torch::Tensor& m2) const {
    auto h = m1.defined() ? f * m1 : f;
    h = torch::relu(torch::linear(h, w3, b3));
    if (m2.defined()) h = h * m2;
    return torch::linear(h, w4, b4);
  }

  // Masks for rows = n_crops * mc; each crop's masks come from its own stream so a crop's
  // result does not depend on the other crops in the batch.
  std::pair<torch::Tensor, torch::Tensor> mc_masks(int64_t n_crops, int64_t mc, uint64_t seed) const {
    const int64_t F = features(), H = cfg.hidden;
    std::vector<float> m1(static_cast<size_t>(n_crops * mc * F)), m2(static_cast<size_t>(n_crops * mc * H));
    for (int64_t i = 0; i < n_crops; ++i) {
      Rng rng(derive_seed(seed, kMcStream, static_cast<uint64_t>(i)));
      fill_mask(m1.data() + i * mc * F, mc, F, cfg.dropout, rng);
      fill_mask(m2.data() + i * mc * H, mc, H, cfg.dropout, rng);
    }
    return {torch::from_blob(m1.data(), {n_crops * mc, F}, torch::kFloat32).clone(),
            torch::from_blob(m2.data(), {n_crops * mc, H}, torch::kFloat32).clone()};
  }

  // [N * mc, C] softmax probabilities of the MC passes.
  torch::Tensor mc_forward(const std::vector<cv::Mat>& crops, uint64_t seed) const {
    torch::NoGradGuard no_grad;
    const int64_t n = static_cast<int64_t>(crops.size());
    const int64_t mc = std::max(1, cfg.mc_samples);
    const torch::Tensor f = trunk(batch(crops)).repeat_interleave(mc, 0);
    const auto [m1, m2] = mc_masks(n, mc, seed);
    return torch::softmax(head(f, m1, m2), 1);
  }
};

class TorchModel final : public torch_backend::Model {
 public:
  explicit TorchModel(Net net) : net_(std::move(net)) {}
  const ClassifierConfig& config() const override { return net_.cfg; }
  const std::vector<SemanticClass>& classes() const override { return net_.classes; }
  std::string serialize() const override;
  std::vector<Prediction> classify(const std::vector<cv::Mat>& crops, uint64_t seed) const override;
  std::vector<std::vector<float>> mc_probabilities(const cv::Mat& crop, uint64_t seed) const override;
  std::vector<std::vector<float>> probabilities(const std::vector<cv::Mat>& crops) const override;
  double train(const std::vector<LabelledCrop>& data, const TrainConfig& config, uint64_t seed) override;

 private:
  Net net_;
};

std::string TorchModel::serialize() const {
  torch::serialize::OutputArchive ar;
  const ClassifierConfig& c = net_.cfg;
  ar.write("arch", torch::tensor(std::vector<int64_t>{c.input_px, c.conv1_channels, c.conv2_channels, c.hidden}));
  ar.write("dropout", torch::tensor(std::vector<double>{c.dropout}));
  std::vector<int64_t> cls;
  for (SemanticClass s : net_.classes) cls.push_back(static_cast<int64_t>(s));
  ar.write("classes", torch::tensor(cls));
  const char* names[] = {"w1", "b1", "w2", "b2", "w3", "b3", "w4", "b4"};
  const auto ps = net_.params();
  for (size_t i = 0; i < ps.size(); ++i) ar.write(names[i], ps[i]->detach());
  std::ostringstream os;
  ar.save_to(os);
  return os.str();
}



std::vector<Prediction> TorchModel::classify(const std::vector<cv::Mat>& crops, uint64_t seed) const {
  std::vector<Prediction> out(crops.size());
  if (crops.empty()) return out;
  const int64_t mc = std::max(1, net_.cfg.mc_samples);
  const int64_t n_cls = static_cast<int64_t>(net_.classes.size());
  const torch::Tensor mean = net_.mc_forward(crops, seed).reshape({static_cast<int64_t>(crops.size()), mc, n_cls}).mean(1).contiguous();
  const float* m = mean.data_ptr<float>();
  for (size_t i = 0; i < crops.size(); ++i) {
    Prediction& p = out[i];
    p.mean_probabilities.assign(m + static_cast<int64_t>(i) * n_cls, m + (static_cast<int64_t>(i) + 1) * n_cls);
    const auto best = std::max_element(p.mean_probabilities.begin(), p.mean_probabilities.end());
    p.class_index = static_cast<int>(best - p.mean_probabilities.begin());
    p.mean_probability = *best;
    p.known = p.mean_probability > net_.cfg.accept_probability;
    if (p.known) p.semantic = net_.classes[static_cast<size_t>(p.class_index)];
  }
  return out;
}

std::vector<std::vector<float>> TorchModel::mc_probabilities(const cv::Mat& crop, uint64_t seed) const {
  const torch::Tensor p = net_.mc_forward({crop}, seed).contiguous();
  std::vector<std::vector<float>> out(static_cast<size_t>(p.size(0)));
  const float* d = p.data_ptr<float>();
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].assign(d + static_cast<int64_t>(i) * p.size(1), d + (static_cast<int64_t>(i) + 1) * p.size(1));
  }
  return out;
}

std::vector<std::vector<float>> TorchModel::probabilities(const std::vector<cv::Mat>& crops) const {
  std::vector<std::vector<float>> out(crops.size());
  if (crops.empty()) return out;
  torch::NoGradGuard no_grad;
  const torch::Tensor p = torch::softmax(net_.head(net_.trunk(net_.batch(crops)), {}, {}), 1).contiguous();
  const float* d = p.data_ptr<float>();
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].assign(d + static_cast<int64_t>(i) * p.size(1), d + (static_cast<int64_t>(i) + 1) * p.size(1));
  }
  return out;
}

double TorchModel::train(const std::vector<LabelledCrop>& data, const TrainConfig& config, uint64_t seed) {
  if (data.empty()) return 0.0;
  // Every batch allocates and frees the same tensor buffers. With glibc's default thresholds
  // the large ones go back to the kernel on free and are faulted in again on the next batch:
  // 10 million page faults and ~70 % of the time of the default training. Keep them in the heap.
  ::mallopt(M_MMAP_THRESHOLD, 64 << 20);
  ::mallopt(M_TRIM_THRESHOLD, 256 << 20);
  Net& m = net_;
  std::vector<torch::Tensor> params;
  for (torch::Tensor* t : m.params()) {
    *t = t->detach().clone().set_requires_grad(true);
    params.push_back(*t);
  }
  torch::optim::Adam opt(params, torch::optim::AdamOptions(config.learning_rate).weight_decay(config.weight_decay));
  std::vector<size_t> order(data.size());
  std::iota(order.begin(), order.end(), size_t{0});
  double last_loss = 0.0;
  const int64_t F = m.features(), H = m.cfg.hidden;
  for (int epoch = 0; epoch < config.epochs; ++epoch) {
    Rng rng(derive_seed(seed, kShuffleStream, static_cast<uint64_t>(epoch)));
    for (size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);  // Fisher-Yates
    Rng drop(derive_seed(seed, kTrainDropoutStream, static_cast<uint64_t>(epoch)));
    double sum = 0.0;
    size_t batches = 0;
    for (size_t start = 0; start < order.size(); start += static_cast<size_t>(config.batch)) {
      const size_t end = std::min(order.size(), start + static_cast<size_t>(config.batch));
      std::vector<cv::Mat> crops;
      std::vector<int64_t> labels;
      for (size_t k = start; k < end; ++k) {
        crops.push_back(data[order[k]].crop);
        labels.push_back(data[order[k]].label);
      }
      const int64_t b = static_cast<int64_t>(crops.size());
      std::vector<float> m1(static_cast<size_t>(b * F)), m2(static_cast<size_t>(b * H));
      fill_mask(m1.data(), b, F, m.cfg.dropout, drop);
      fill_mask(m2.data(), b, H, m.cfg.dropout, drop);
      const auto t1 = torch::from_blob(m1.data(), {b, F}, torch::kFloat32).clone();
      const auto t2 = torch::from_blob(m2.data(), {b, H}, torch::kFloat32).clone();
      const auto logits = m.head(m.trunk(m.batch(crops)), t1, t2);
      const auto loss = torch::nll_loss(torch::log_softmax(logits, 1), torch::tensor(labels));
      opt.zero_grad();
      loss.backward();
      opt.step();
      sum += loss.item<double>();
      ++batches;
    }
    last_loss = sum / static_cast<double>(std::max<size_t>(1, batches));
  }
  for (torch::Tensor* t : m.params()) *t = t->detach();
  return last_loss;
}

using torch_backend::Model;


Model* create(const ClassifierConfig& config, const std::vector<SemanticClass>& classes, uint64_t init_seed) {
  Net net;
  net.cfg = config;
  net.classes = classes;
  net.init(init_seed);
  return new TorchModel(std::move(net));
}

Model* deserialize(const std::string& bytes, const ClassifierConfig& runtime, std::string* error) {
  const auto fail = [error](std::string what) -> Model* {
    *error = std::move(what);
    return nullptr;
  };
  try {
    std::istringstream is(bytes);
    torch::serialize::InputArchive ar;
    ar.load_from(is);
    Net net;
    net.cfg = runtime;
    torch::Tensor arch, dropout, cls;
    ar.read("arch", arch);
    ar.read("dropout", dropout);
    ar.read("classes", cls);
    if (arch.numel() != 4 || dropout.numel() != 1 || cls.numel() < 1) return fail("model: bad header tensors");
    net.cfg.input_px = static_cast<int>(arch[0].item<int64_t>());
    net.cfg.conv1_channels = static_cast<int>(arch[1].item<int64_t>());
    net.cfg.conv2_channels = static_cast<int>(arch[2].item<int64_t>());
    net.cfg.hidden = static_cast<int>(arch[3].item<int64_t>());
    net.cfg.dropout = dropout[0].item<double>();
    for (int64_t i = 0; i < cls.numel(); ++i) {
      const int64_t v = cls[i].item<int64_t>();
      if (v < 0 || v >= kSemanticClassCount) return fail("model: unknown semantic class " + std::to_string(v));
      net.classes.push_back(static_cast<SemanticClass>(v));
    }
    const char* names[] = {"w1", "b1", "w2", "b2", "w3", "b3", "w4", "b4"};
    const auto ps = net.params();
    for (size_t i = 0; i < ps.size(); ++i) ar.read(names[i], *ps[i]);
    // Shape check: one deterministic forward of a blank crop.
    const int64_t px = net.cfg.input_px;
    torch::NoGradGuard no_grad;
    const auto out = net.head(net.trunk(torch::zeros({1, 1, px, px})), {}, {});
    if (out.size(1) != static_cast<int64_t>(net.classes.size())) return fail("model: class count mismatch");
    return new TorchModel(std::move(net));
  } catch (const c10::Error& e) {
    return fail(std::string("model: cannot read torch archive: ") + e.what_without_backtrace());
  }
}

const torch_backend::Api kApi{torch_backend::kAbiVersion, sizeof(ClassifierConfig), &pin_onednn, &status,
                              &set_threads,  &manual_seed, &create, &deserialize};

}  // namespace
}  // namespace orthosonar::inference

extern "C" __attribute__((visibility("default"))) const orthosonar::inference::torch_backend::Api* orthosonar_torch_api() {
  return &orthosonar::inference::kApi;
}

