#include "s4d/nn/dino_vit.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>

#include "s4d/nn/attention.h"
#include "s4d/nn/torch_cubic.h"
#include "s4d/nn/weights.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

[[noreturn]] void fail(const io::SafetensorsFile& file, const std::string& what) {
  throw std::invalid_argument(file.path().string() + ": " + what);
}

// The dimension `dim` of a stored tensor, which must have `rank` dimensions.
uint32_t dimension(const io::SafetensorsFile& file, const std::string& name, size_t rank, size_t dim) {
  const std::vector<int64_t>& s = file.shape(name);
  if (s.size() != rank || s[dim] <= 0 || s[dim] > int64_t{S4D_NN_MAX_LOOP})
    fail(file, name + " has shape " + io::shape_text(s) + ", expected " + std::to_string(rank) +
                   " dimensions with dimension " + std::to_string(dim) + " in 1.." + std::to_string(S4D_NN_MAX_LOOP));
  return static_cast<uint32_t>(s[dim]);
}

VitShape read_shape(const io::SafetensorsFile& file, uint32_t heads) {
  VitShape s;
  s.width = dimension(file, "cls_token", 3, 2);
  s.patch = dimension(file, "patch_embed.proj.weight", 4, 2);
  const uint32_t tokens = static_cast<uint32_t>(file.shape("pos_embed").size() == 3 ? file.shape("pos_embed")[1] : 0);
  s.grid = static_cast<uint32_t>(std::lround(std::sqrt(double(tokens > 0 ? tokens - 1 : 0))));
  if (tokens < 2 || s.grid * s.grid + 1 != tokens)
    fail(file, "pos_embed has shape " + io::shape_text(file.shape("pos_embed")) + ", not [1, 1 + g^2, width]");
  while (file.contains("blocks." + std::to_string(s.depth) + ".norm1.weight")) ++s.depth;
  if (s.depth == 0) fail(file, "holds no blocks.0.norm1.weight: not a DINO ViT state dict");
  s.hidden = dimension(file, "blocks.0.mlp.fc1.weight", 2, 0);
  s.heads = heads != 0 ? heads : s.width / kVitHeadWidth;
  if (s.heads == 0 || s.width % s.heads != 0)
    fail(file, "width " + std::to_string(s.width) + " does not split into " + std::to_string(s.heads) + " heads");
  if (3 * s.patch * s.patch > S4D_NN_MAX_LOOP) fail(file, "patch " + std::to_string(s.patch) + " is too large for the kernels");
  return s;
}

// Per output index: the first tap (floor of the source coordinate) and the four weights.
struct Taps {
  std::vector<int64_t> first;
  std::vector<std::array<double, 4>> w;
};

Taps cubic_taps(uint32_t out, double scale) {
  Taps t;
  for (uint32_t i = 0; i < out; ++i) {
    const double src = (i + 0.5) / scale - 0.5;
    const double f = std::floor(src);
    t.first.push_back(static_cast<int64_t>(f));
    t.w.push_back(torch_cubic_weights(src - f));
  }
  return t;
}

}  // namespace

std::vector<double> dino_position_embedding(const std::vector<float>& pos, const std::vector<float>& cls,
                                            const VitShape& shape, uint32_t image_h, uint32_t image_w) {
  const uint32_t d = shape.width, g = shape.grid, gh = image_h / shape.patch, gw = image_w / shape.patch;
  if (pos.size() != size_t{d} * (1 + g * g) || cls.size() != d)
    throw std::invalid_argument("dino_position_embedding: pos / cls do not match width " + std::to_string(d));
  if (gh == 0 || gw == 0)
    throw std::invalid_argument("dino_position_embedding: a " + std::to_string(image_h) + "x" + std::to_string(image_w) +
                                " image is smaller than one " + std::to_string(shape.patch) + "-pixel patch");
  const size_t n = 1 + size_t{gh} * gw;
  std::vector<double> out(d * n);
  for (uint32_t c = 0; c < d; ++c) out[c * n] = double(cls[c]) + double(pos[c]);
  const auto stored = [&](int64_t y, int64_t x, uint32_t c) { return double(pos[(1 + size_t(y) * g + size_t(x)) * d + c]); };
  if (size_t{gh} * gw == size_t{g} * g && image_h == image_w) {
    for (uint32_t c = 0; c < d; ++c)
      for (size_t t = 1; t < n; ++t) out[c * n + t] = double(pos[t * d + c]);
    return out;
  }
  const double sy = (gh + 0.1) / g, sx = (gw + 0.1) / g;
  // PyTorch's output size floor(g * scale), which DINO asserts to be the patch grid.
  if (uint32_t(std::floor(g * sy)) != gh || uint32_t(std::floor(g * sx)) != gw)
    throw std::logic_error("dino_position_embedding: the interpolated grid is not " + std::to_string(gh) + "x" + std::to_string(gw));
  const Taps ty = cubic_taps(gh, sy), tx = cubic_taps(gw, sx);
  const auto clamp = [&](int64_t i) { return std::min<int64_t>(std::max<int64_t>(i, 0), g - 1); };
  for (uint32_t c = 0; c < d; ++c)
    for (uint32_t y = 0; y < gh; ++y)
      for (uint32_t x = 0; x < gw; ++x) {
        double acc = 0;
        for (int i = 0; i < 4; ++i) {
          double row = 0;
          for (int j = 0; j < 4; ++j) row += tx.w[x][j] * stored(clamp(ty.first[y] - 1 + i), clamp(tx.first[x] - 1 + j), c);
          acc += ty.w[y][i] * row;
        }
        out[c * n + 1 + size_t{y} * gw + x] = acc;
      }
  return out;
}

DinoVit::DinoVit(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads)
    : ctx_(ctx), shape_(read_shape(file, heads)) {
  const VitShape& s = shape_;
  cls_ = file.read("cls_token", {1, 1, s.width});
  pos_ = file.read("pos_embed", {1, 1 + s.grid * s.grid, s.width});
  patch_ = load_conv(ctx, file, "patch_embed.proj", 3, s.width, s.patch);
  for (uint32_t i = 0; i < s.depth; ++i) {
    const std::string b = "blocks." + std::to_string(i) + ".";
    blocks_.push_back({load_norm(ctx, file, b + "norm1", s.width), load_norm(ctx, file, b + "norm2", s.width),
                       upload_qkv(ctx, file.path().filename().string() + " " + b + "attn.qkv", s.width, s.heads,
                                  file.read(b + "attn.qkv.weight", {3 * s.width, s.width}),
                                  file.read(b + "attn.qkv.bias", {3 * s.width})),
                       load_linear(ctx, file, b + "attn.proj", s.width, s.width),
                       load_linear(ctx, file, b + "mlp.fc1", s.width, s.hidden),
                       load_linear(ctx, file, b + "mlp.fc2", s.hidden, s.width)});
  }
  norm_ = load_norm(ctx, file, "norm", s.width);
}

const Tensor& DinoVit::position(uint32_t image_h, uint32_t image_w) const {
  // Keyed by the image size, not the grid: the stored grid is used as is only for square images.
  const std::pair<uint32_t, uint32_t> size{image_h, image_w};
  auto it = positions_.find(size);
  if (it == positions_.end()) {
    const std::vector<double> p = dino_position_embedding(pos_, cls_, shape_, image_h, image_w);
    const std::vector<float> f(p.begin(), p.end());
    const auto tokens = static_cast<uint32_t>(f.size() / shape_.width);
    it = positions_.emplace(size, upload_tensor(ctx_, "dino position embedding", shape_.width, 1, tokens, f)).first;
  }
  return it->second;
}

std::vector<float> DinoVit::cls(const Tensor& image) const {
  if (image.c != 3 || image.h < shape_.patch || image.w < shape_.patch)
    throw std::invalid_argument("dino vit: needs an RGB image of at least " + std::to_string(shape_.patch) + "x" +
                                std::to_string(shape_.patch) + " pixels, got " + image.shape());
  const Tensor& pos = position(image.h, image.w);
  engine::Recorder rec(ctx_, "dino vit");
  Tensor x = vit_embed(rec, conv_strided(rec, image, patch_, shape_.patch, 0, false), pos);
  for (const TransformerBlock& b : blocks_) x = transformer_block(rec, b, shape_.heads, kVitNormEps, std::move(x));
  const Tensor y = layernorm(rec, x, norm_, kVitNormEps);
  ctx_.run(std::move(rec));
  const std::vector<float> all = download(ctx_, y);
  std::vector<float> out(shape_.width);
  for (uint32_t c = 0; c < shape_.width; ++c) out[c] = all[size_t{c} * y.w];
  return out;
}

}  // namespace s4d::nn
