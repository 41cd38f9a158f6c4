#include "s4d/stylizer_train/stylizer_trainer.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>

#include "s4d/io/image_file.h"
#include "s4d/io/safetensors.h"
#include "s4d/nn/vgg.h"
#include "s4d/optim/adam.h"
#include "s4d/stylizer_train/checkpoint.h"
#include "s4d/stylizer_train/loss_sets.h"

namespace s4d::stylizer_train {

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> list_images(const fs::path& dir, const char* option) {
  if (!fs::is_directory(dir)) throw std::invalid_argument(std::string(option) + " " + dir.string() + " is not a folder");
  std::vector<fs::path> images;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) images.push_back(e.path());
  }
  if (images.empty()) throw std::invalid_argument(std::string(option) + " " + dir.string() + " holds no PNG or JPEG image");
  std::sort(images.begin(), images.end());
  return images;
}

// The widths of relu1_1 .. relu5_1 from vgg_normalised's convolutions that end each level.
nn::VggWidths widths_of(const io::SafetensorsFile& vgg) {
  nn::VggWidths w;
  const char* ends[5] = {"2.weight", "9.weight", "16.weight", "29.weight", "42.weight"};
  for (int l = 0; l < 5; ++l) w.level[l] = static_cast<uint32_t>(vgg.shape(ends[l]).at(0));
  return w;
}

// PyTorch's default Conv2d / Linear initialisation: weights and biases uniform in +-1/sqrt(fan_in).
void add_random(std::vector<io::NamedTensor>& out, const std::string& prefix, uint32_t cin, uint32_t cout, uint32_t k,
                bool linear, std::mt19937_64& rng) {
  const float bound = 1.0f / std::sqrt(static_cast<float>(cin * k * k));
  std::uniform_real_distribution<float> u(-bound, bound);
  io::NamedTensor w{prefix + ".weight", {}, std::vector<float>(size_t{cout} * cin * k * k)};
  w.shape = linear ? std::vector<int64_t>{cout, cin} : std::vector<int64_t>{cout, cin, k, k};
  for (float& v : w.values) v = u(rng);
  io::NamedTensor b{prefix + ".bias", {cout}, std::vector<float>(cout)};
  for (float& v : b.values) v = u(rng);
  out.push_back(std::move(w));
  out.push_back(std::move(b));
}

void write_random_init(const fs::path& dir, const nn::VggWidths& widths, uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x5eedULL);
  const auto& w = widths.level;
  std::vector<io::NamedTensor> dec;
  const struct {
    int index;
    uint32_t cin, cout;
  } convs[] = {{1, w[3], w[2]}, {5, w[2], w[2]}, {8, w[2], w[2]}, {11, w[2], w[2]}, {14, w[2], w[1]},
               {18, w[1], w[1]}, {21, w[1], w[0]}, {25, w[0], w[0]}, {28, w[0], 3}};
  for (const auto& c : convs) add_random(dec, std::to_string(c.index), c.cin, c.cout, 3, false, rng);
  io::write_safetensors(dir / "decoder.safetensors", dec);
  std::vector<io::NamedTensor> mcc;
  for (const char* p : {"MCCN.f", "MCCN.g", "MCCN.out_conv"}) add_random(mcc, p, w[3], w[3], 1, false, rng);
  add_random(mcc, "MCCN.fc", w[3], w[3], 1, true, rng);
  io::write_safetensors(dir / "mcc_module.safetensors", mcc);
}

// CCPL's projection heads, one per level: Linear(C, C), ReLU, Linear(C, C / 4) at PyTorch's default
// initialisation from the seed, named as CCPL's Sequential ("ccpl_heads.<level>.0", ".2").
std::vector<nn::CcplHead> random_heads(engine::Context& ctx, const nn::CcplConfig& config, const nn::VggWidths& widths,
                                       uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0xcc91ULL);
  std::vector<nn::CcplHead> heads;
  for (const int l : config.levels) {
    const uint32_t c = widths.level[l - 1];
    if (c < 4)
      throw std::invalid_argument("--vgg: relu" + std::to_string(l) + "_1 has " + std::to_string(c) +
                                  " channels; a CCPL head Linear(C, C / 4) needs at least 4");
    std::vector<io::NamedTensor> t;
    const std::string prefix = "ccpl_heads." + std::to_string(l);
    add_random(t, prefix + ".0", c, c, 1, true, rng);
    add_random(t, prefix + ".2", c, c / 4, 1, true, rng);
    heads.push_back({nn::upload_conv(ctx, prefix + ".0", c, c, 1, t[0].values, t[1].values),
                     nn::upload_conv(ctx, prefix + ".2", c, c / 4, 1, t[2].values, t[3].values)});
  }
  return heads;
}

void save(engine::Context& ctx, const fs::path& path, int step,
          const std::vector<std::pair<std::string, const nn::ConvWeights*>>& params, const std::vector<bool>& linear) {
  std::vector<io::NamedTensor> out;
  for (size_t i = 0; i < params.size(); ++i) {
    const nn::ConvWeights& w = *params[i].second;
    io::NamedTensor t{params[i].first + ".weight", {}, ctx.download<float>(w.weight, w.weight.size() / sizeof(float))};
    t.shape = linear[i] ? std::vector<int64_t>{w.cout, w.cin} : std::vector<int64_t>{w.cout, w.cin, w.k, w.k};
    out.push_back(std::move(t));
    out.push_back({params[i].first + ".bias", {w.cout}, ctx.download<float>(w.bias, w.cout)});
  }
  const fs::path tmp = path.string() + ".tmp";
  io::write_safetensors(tmp, out, io::TensorDtype::f32, {{"step", std::to_string(step)}});
  fs::rename(tmp, path);
}

// A random crop x crop window of one image resized to resize x resize, as [3, crop, crop].
std::vector<float> sample(const io::ImageF& image, int crop, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> ux(0, image.width - crop), uy(0, image.height - crop);
  const int x0 = ux(rng), y0 = uy(rng);
  std::vector<float> chw(size_t{3} * crop * crop);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < crop; ++y)
      for (int x = 0; x < crop; ++x)
        chw[(size_t(c) * crop + y) * crop + x] = image.data[(size_t(y0 + y) * image.width + x0 + x) * 3 + c];
  return chw;
}

std::vector<io::ImageF> load_all(const std::vector<fs::path>& paths, int size) {
  std::vector<io::ImageF> images;
  for (const fs::path& p : paths) images.push_back(io::resize_image(io::read_image_rgb(p), size, size));
  return images;
}

bool same_bytes(const fs::path& a, const fs::path& b) {
  if (!fs::exists(b) || fs::file_size(a) != fs::file_size(b)) return false;
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  return std::equal(std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(fb));
}

// The options a continued run must repeat, as the checkpoint's metadata records them.
std::vector<std::pair<std::string, std::string>> kept_settings(const StylizerTrainSettings& s) {
  char lr[32];  // the shortest of 15 or 17 digits that reads back as the same double
  std::snprintf(lr, sizeof lr, "%.15g", s.lr);
  if (std::strtod(lr, nullptr) != s.lr) std::snprintf(lr, sizeof lr, "%.17g", s.lr);
  return {{"batch", std::to_string(s.batch)}, {"crop", std::to_string(s.crop)}, {"resize", std::to_string(s.resize)},
          {"lr", lr}, {"seed", std::to_string(s.seed)}};
}

// The steps out's checkpoint has done, after checking that it may be continued; 0 for a fresh start.
int steps_done(const StylizerTrainSettings& s) {
  const fs::path checkpoint = s.out / "checkpoint.safetensors";
  if (fs::exists(s.out) && !fs::is_directory(s.out)) throw std::invalid_argument("--out " + s.out.string() + " is not a folder");
  if (s.restart || !fs::exists(s.out) || fs::is_empty(s.out)) return 0;
  if (!fs::exists(checkpoint))
    throw std::invalid_argument("--out " + s.out.string() + " holds files but no checkpoint.safetensors to continue; pass --restart to train it from the start");
  const std::vector<std::pair<std::string, std::string>> settings = kept_settings(s);
  std::vector<std::string> keys;
  for (const auto& kv : settings) keys.push_back(kv.first);
  const CheckpointState state = read_checkpoint_state(checkpoint, keys);
  if (state.losses != s.losses)
    throw std::invalid_argument("--losses " + s.losses + ": " + checkpoint.string() + " was trained with --losses " + state.losses +
                                "; pass --restart to start over");
  for (size_t i = 0; i < settings.size(); ++i)
    if (state.settings[i].second != settings[i].second)
      throw std::invalid_argument("--" + settings[i].first + " " + settings[i].second + ": " + checkpoint.string() +
                                  " was trained with --" + settings[i].first + " " + state.settings[i].second +
                                  "; pass --restart to start over");
  if (!s.init.empty())
    throw std::invalid_argument("--init: --out " + s.out.string() + " continues from its checkpoint; pass --restart to start over from --init");
  if (state.step >= s.steps)
    throw std::invalid_argument("--steps " + std::to_string(s.steps) + ": " + checkpoint.string() + " is already at step " +
                                std::to_string(state.step));
  for (const char* file : {"decoder.safetensors", "mcc_module.safetensors"}) {
    const int step = weights_step(s.out / file);
    if (step != state.step)
      throw std::runtime_error((s.out / file).string() + " is at step " + std::to_string(step) + ", " + checkpoint.string() +
                               " at step " + std::to_string(state.step) + "; pass --restart to start over");
  }
  const fs::path vgg_copy = s.out / "vgg_normalised.safetensors";
  if (fs::absolute(s.vgg) != fs::absolute(vgg_copy) && !same_bytes(s.vgg, vgg_copy))
    throw std::invalid_argument("--vgg " + s.vgg.string() + " is not the encoder " + vgg_copy.string() +
                                " was trained with; pass --restart to start over");
  return state.step;
}

}  // namespace

double hgst_learning_rate(double lr, int step) { return lr / (1.0 + 5e-5 * static_cast<double>(step / 2000)); }

std::vector<nn::MccLossValues> train_stylizer(engine::Context& ctx, const StylizerTrainSettings& s, const StepFn& on_step) {
  if (s.steps < 1) throw std::invalid_argument("--steps: expected 1 or more, got " + std::to_string(s.steps));
  if (s.batch < 1) throw std::invalid_argument("--batch: expected 1 or more, got " + std::to_string(s.batch));
  if (s.save_every < 1) throw std::invalid_argument("--save-every: expected 1 or more, got " + std::to_string(s.save_every));
  if (s.crop < 40 || s.crop % 8 != 0) throw std::invalid_argument("--crop: expected a multiple of 8, at least 40, got " + std::to_string(s.crop));
  if (s.resize < s.crop) throw std::invalid_argument("--resize " + std::to_string(s.resize) + " is smaller than --crop " + std::to_string(s.crop));
  if (!(s.lr > 0)) throw std::invalid_argument("--lr: expected a positive learning rate");
  const LossSet loss = loss_set(s.losses);
  const int done = steps_done(s);
  const std::vector<io::ImageF> contents = load_all(list_images(s.content_dir, "--content"), s.resize);
  const std::vector<io::ImageF> styles = load_all(list_images(s.styles_dir, "--styles"), s.resize);
  const io::SafetensorsFile vgg_file(s.vgg);
  const fs::path checkpoint = s.out / "checkpoint.safetensors";
  fs::create_directories(s.out);
  if (done == 0) fs::remove(checkpoint);  // a fresh start (--restart): the stale one goes only once the inputs read
  const nn::VggWidths widths = widths_of(vgg_file);
  fs::path init = done > 0 ? s.out : s.init;
  if (init.empty()) {
    write_random_init(s.out, widths, s.seed);
    init = s.out;
  }
  const nn::VggEncoder encoder(ctx, vgg_file, 5, widths);
  const nn::VggDecoder decoder(ctx, io::SafetensorsFile(init / "decoder.safetensors"), widths);
  const nn::MccModule mcc(ctx, io::SafetensorsFile(init / "mcc_module.safetensors"), widths.level[3]);
  if (fs::absolute(s.vgg) != fs::absolute(s.out / "vgg_normalised.safetensors"))
    fs::copy_file(s.vgg, s.out / "vgg_normalised.safetensors", fs::copy_options::overwrite_existing);
  const nn::MccTrainee net{encoder, decoder, mcc};
  std::vector<nn::CcplHead> heads = random_heads(ctx, loss.ccpl, widths, s.seed);
  std::vector<CheckpointTensor> head_tensors;
  for (nn::CcplHead& h : heads)
    for (nn::ConvWeights* w : {&h.first, &h.second})
      head_tensors.insert(head_tensors.end(), {{w->name + ".weight", &w->weight}, {w->name + ".bias", &w->bias}});
  if (done > 0) read_checkpoint_tensors(ctx, checkpoint, head_tensors);  // trained or not, as the run saved them

  // Every parameter tensor (weights, then biases) with its Adam moments, named as in the weights files.
  std::vector<const engine::Buffer*> params;
  std::vector<std::string> names;
  auto add_params = [&](const std::string& file, const std::string& name, const nn::ConvWeights& w) {
    params.insert(params.end(), {&w.weight, &w.bias});
    names.insert(names.end(), {file + "." + name + ".weight", file + "." + name + ".bias"});
  };
  for (const auto& [name, w] : decoder.parameters()) add_params("decoder", name, *w);
  for (const auto& [name, w] : mcc.parameters()) add_params("mcc_module", name, *w);
  if (loss.ccpl.train_heads)  // CCPL's optimiser holds its heads; HGST's does not
    for (const nn::CcplHead& h : heads)
      for (const nn::ConvWeights* w : {&h.first, &h.second}) {
        params.insert(params.end(), {&w->weight, &w->bias});
        names.insert(names.end(), {w->name + ".weight", w->name + ".bias"});
      }
  std::vector<optim::AdamTensor> moments;  // the gradients are new every step
  for (size_t i = 0; i < params.size(); ++i)
    moments.emplace_back(ctx, names[i], *params[i], nullptr, params[i]->size() / sizeof(float));
  if (done > 0) read_checkpoint_moments(checkpoint, moments);
  std::vector<std::pair<std::string, const nn::ConvWeights*>> mcc_params;
  for (const auto& p : mcc.parameters()) mcc_params.push_back(p);
  // The weights first, then the checkpoint: an interruption between them leaves steps that disagree.
  auto save_all = [&](int step) {
    save(ctx, s.out / "decoder.safetensors", step, decoder.parameters(), std::vector<bool>(decoder.parameters().size(), false));
    save(ctx, s.out / "mcc_module.safetensors", step, mcc_params, {false, false, false, true});
    write_checkpoint(ctx, checkpoint, {step, s.losses, kept_settings(s)}, moments, head_tensors);
  };
  optim::Adam adam(ctx, 1, "stylizer adam");
  std::uniform_int_distribution<size_t> pick_content(0, contents.size() - 1), pick_style(0, styles.size() - 1);
  std::vector<nn::MccLossValues> losses;
  // A batch's loss is the mean over its pairs of every term but TV, which HGST sums.
  nn::MccLossWeights per_pair = loss.weights;
  for (float* w : {&per_pair.content, &per_pair.style, &per_pair.identity1, &per_pair.identity2, &per_pair.noise,
                   &per_pair.selfsim, &per_pair.ccpl})
    *w /= static_cast<float>(s.batch);
  const auto crop = static_cast<uint32_t>(s.crop);
  for (int step = done + 1; step <= s.steps; ++step) {
    // The step's own random stream, so a continued run draws what an uninterrupted one would.
    std::seed_seq seeds{static_cast<uint32_t>(s.seed), static_cast<uint32_t>(s.seed >> 32), static_cast<uint32_t>(step)};
    std::mt19937_64 rng(seeds);
    nn::MccGrads grads;
    std::vector<nn::ConvGrads> head_grads;
    {
      engine::Recorder rec(ctx, "stylizer gradients");
      grads = nn::zero_mcc_grads(rec, net);
      if (loss.ccpl.train_heads)
        for (const nn::CcplHead& h : heads)
          for (const nn::ConvWeights* w : {&h.first, &h.second}) head_grads.push_back(nn::zero_conv_grads(rec, *w));
      ctx.run(std::move(rec));
    }
    // MCCNet's and HGST's noise: sigma ~ U(0.01, 0.02) per batch, then N(0, sigma^2) per value, not clamped.
    std::normal_distribution<float> noise(0.0f, std::uniform_real_distribution<float>(0.01f, 0.02f)(rng));
    nn::MccLossValues step_loss;
    for (int b = 0; b < s.batch; ++b) {  // one submission per pair: the tapes of one pair at a time
      const std::vector<float> c = sample(contents[pick_content(rng)], s.crop, rng);
      const std::vector<float> st = sample(styles[pick_style(rng)], s.crop, rng);
      std::vector<float> noisy = c;
      for (float& v : noisy) v += noise(rng);
      // CCPL's anchors on each level (relu<l>_1 is crop / 2^(l - 1) square); a level with fewer
      // interior positions than anchors (crops under 48 for HGST's 16 on relu4_1) takes them all.
      nn::MccCcplInputs ccpl{loss.ccpl, &heads, {}, loss.ccpl.train_heads ? &head_grads : nullptr};
      for (const int l : loss.ccpl.levels) {
        const uint32_t size = crop >> (l - 1);
        const int interior = static_cast<int>((size - 2) * (size - 2));
        ccpl.samples.push_back(nn::draw_ccpl_samples(size, size, std::min(loss.ccpl.anchors, interior), loss.ccpl.jitter, rng));
      }
      const nn::Tensor content = nn::upload_tensor(ctx, "content", 3, crop, crop, c);
      const nn::Tensor content_noise = nn::upload_tensor(ctx, "content + noise", 3, crop, crop, noisy);
      const nn::Tensor style = nn::upload_tensor(ctx, "style", 3, crop, crop, st);
      engine::Recorder rec(ctx, "stylizer step " + std::to_string(step));
      const nn::MccLossRecord record = nn::record_mcc_loss(rec, net, content, style, content_noise, loss.levels, per_pair, ccpl, grads);
      ctx.run(std::move(rec));
      const nn::MccLossValues v = record.values(ctx, per_pair);
      const double share = 1.0 / s.batch;  // the terms' means over the batch, the batch's total
      step_loss.content += share * v.content, step_loss.style += share * v.style;
      step_loss.identity1 += share * v.identity1, step_loss.identity2 += share * v.identity2;
      step_loss.noise += share * v.noise, step_loss.tv += share * v.tv, step_loss.selfsim += share * v.selfsim;
      step_loss.ccpl += share * v.ccpl;
      step_loss.total += v.total;
    }
    std::vector<const engine::Buffer*> g;
    for (const nn::ConvGrads& cg : grads.decoder) g.insert(g.end(), {&cg.weight, &cg.bias});
    for (const nn::ConvGrads& cg : grads.mcc) g.insert(g.end(), {&cg.weight, &cg.bias});
    for (const nn::ConvGrads& cg : head_grads) g.insert(g.end(), {&cg.weight, &cg.bias});
    adam.set_group(0, {.lr = hgst_learning_rate(s.lr, step), .beta1 = 0.9, .beta2 = 0.999, .eps = 1e-8}, static_cast<uint32_t>(step));
    adam.upload();
    engine::Recorder rec(ctx, "stylizer adam " + std::to_string(step));
    for (size_t i = 0; i < params.size(); ++i) moments[i].record(adam, rec, 0, *g[i]);
    ctx.run(std::move(rec));
    losses.push_back(step_loss);
    if (!std::isfinite(losses.back().total))
      throw std::runtime_error("train-stylizer: the loss is not finite at step " + std::to_string(step));
    if (on_step) on_step(step, losses.back());
    if (step % s.save_every == 0 || step == s.steps) save_all(step);
  }
  return losses;
}

}  // namespace s4d::stylizer_train
