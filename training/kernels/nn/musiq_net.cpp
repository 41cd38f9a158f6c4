#include "s4d/nn/musiq_net.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "s4d/nn/group_norm.h"
#include "s4d/nn/weights.h"
#include "s4d_nn.h"

namespace s4d::nn {

namespace {

constexpr uint32_t kRootWidth = 64, kBlockWidth = 256, kGroups = 32;
constexpr uint32_t kMap = MusiqNet::kPatch / 4;        // the root's 8x8 output per patch
constexpr uint32_t kMosaicCell = MusiqNet::kPatch + 4;  // 36 rows: 2 zero rows before a patch, 2 after
constexpr uint32_t kConvCell = kMosaicCell / 2, kPoolCell = kMap + 1;
constexpr float kRootEps = 1e-6f, kBlockEps = 1e-4f, kNormEps = 1e-6f;
constexpr double kStdConvEps = 1e-5;
const std::string kEncoder = "transformer_encoder.";

[[noreturn]] void fail(const io::SafetensorsFile& file, const std::string& what) {
  throw std::invalid_argument(file.path().string() + ": " + what);
}

uint32_t dimension(const io::SafetensorsFile& file, const std::string& name, size_t rank, size_t dim) {
  const std::vector<int64_t>& s = file.shape(name);
  if (s.size() != rank || s[dim] <= 0 || s[dim] > int64_t{S4D_NN_MAX_LOOP})
    fail(file, name + " has shape " + io::shape_text(s) + ", expected " + std::to_string(rank) + " dimensions");
  return static_cast<uint32_t>(s[dim]);
}

// The same values as one row of pixels (1x1 convolutions take nn_conv1x1_rows' wide tiles), and back.
Tensor flat(Tensor t) {
  t.w *= t.h;
  t.h = 1;
  return t;
}

Tensor unflat(Tensor t, uint32_t h, uint32_t w) {
  t.h = h;
  t.w = w;
  return t;
}

std::string block_name(uint32_t i) { return kEncoder + "transformer.encoderblock_" + std::to_string(i) + "."; }

MusiqShape read_shape(const io::SafetensorsFile& file, uint32_t heads) {
  MusiqShape s;
  s.width = dimension(file, "embedding.weight", 2, 0);
  const uint32_t cells = dimension(file, kEncoder + "posembed_input.position_emb", 3, 1);
  s.grid = static_cast<uint32_t>(std::lround(std::sqrt(double(cells))));
  if (s.grid * s.grid != cells) fail(file, "position_emb holds " + std::to_string(cells) + " positions, not a square grid");
  s.scales = dimension(file, kEncoder + "scaleembed_input.scale_emb", 2, 0);
  while (file.contains(block_name(s.depth) + "norm1.weight")) ++s.depth;
  if (s.depth == 0) fail(file, "holds no " + block_name(0) + "norm1.weight: not a pyiqa MUSIQ state dict");
  s.hidden = dimension(file, block_name(0) + "mlp.fc1.weight", 2, 0);
  s.heads = heads != 0 ? heads : s.width / 64;
  if (s.heads == 0 || s.width % s.heads != 0)
    fail(file, "width " + std::to_string(s.width) + " does not split into " + std::to_string(s.heads) + " heads");
  return s;
}

// StdConv(cin, cout, k, bias=False): the stored weight standardised per output channel; `as_1x1`: as
// the 1x1 convolution of im2col's cin k k rows (the same values).
ConvWeights load_std_conv(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& prefix, uint32_t cin,
                          uint32_t cout, uint32_t k, bool as_1x1 = false) {
  std::vector<float> w = file.read(prefix + ".weight", {cout, cin, k, k});
  const size_t n = size_t{cin} * k * k;
  for (uint32_t o = 0; o < cout; ++o) {
    float* f = w.data() + o * n;
    double mean = 0, centred = 0;
    for (size_t i = 0; i < n; ++i) mean += f[i];
    mean /= double(n);
    for (size_t i = 0; i < n; ++i) centred += (f[i] - mean) * (f[i] - mean);
    const double scale = 1.0 / (std::sqrt(centred / double(n - 1)) + kStdConvEps);
    for (size_t i = 0; i < n; ++i) f[i] = float((f[i] - mean) * scale);
  }
  return upload_conv(ctx, file.path().filename().string() + " " + prefix, as_1x1 ? cin * k * k : cin, cout, as_1x1 ? 1 : k, w,
                     std::vector<float>(cout, 0.0f));
}

// embedding = Linear(8 * 8 * 256, width) over (row, column, channel) as a 9x9 convolution over a
// pooled cell, whose row and column 0 are the cell's padding, stored as the 1x1 convolution of its
// im2col rows.
ConvWeights load_embedding(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t width) {
  const std::vector<float> linear = file.read("embedding.weight", {width, kMap * kMap * kBlockWidth});
  std::vector<float> conv(size_t{width} * kBlockWidth * kPoolCell * kPoolCell, 0.0f);
  for (uint32_t o = 0; o < width; ++o)
    for (uint32_t y = 0; y < kMap; ++y)
      for (uint32_t x = 0; x < kMap; ++x)
        for (uint32_t c = 0; c < kBlockWidth; ++c)
          conv[((size_t{o} * kBlockWidth + c) * kPoolCell + y + 1) * kPoolCell + x + 1] =
              linear[size_t{o} * kMap * kMap * kBlockWidth + (size_t{y} * kMap + x) * kBlockWidth + c];
  return upload_conv(ctx, file.path().filename().string() + " embedding", kBlockWidth * kPoolCell * kPoolCell, width, 1, conv,
                     file.read("embedding.bias", {width}));
}

TransformerBlock load_block(engine::Context& ctx, const io::SafetensorsFile& file, const MusiqShape& s, uint32_t i) {
  const std::string b = block_name(i), a = b + "attention.";
  std::vector<float> qkv, qkv_bias;
  for (const char* part : {"query", "key", "value"}) {
    const std::vector<float> w = file.read(a + part + ".weight", {s.width, s.width});
    const std::vector<float> bias = file.read(a + part + ".bias", {s.width});
    qkv.insert(qkv.end(), w.begin(), w.end());
    qkv_bias.insert(qkv_bias.end(), bias.begin(), bias.end());
  }
  return {load_norm(ctx, file, b + "norm1", s.width),
          load_norm(ctx, file, b + "norm2", s.width),
          upload_qkv(ctx, file.path().filename().string() + " " + a + "query/key/value", s.width, s.heads, qkv, qkv_bias),
          load_linear(ctx, file, a + "out", s.width, s.width),
          load_linear(ctx, file, b + "mlp.fc1", s.width, s.hidden),
          load_linear(ctx, file, b + "mlp.fc2", s.hidden, s.width)};
}

}  // namespace

MusiqNet::MusiqNet(engine::Context& ctx, const io::SafetensorsFile& file, uint32_t heads)
    : ctx_(ctx),
      shape_(read_shape(file, heads)),
      conv_root_(load_std_conv(ctx, file, "conv_root", 3, kRootWidth, 7, true)),
      conv1_(load_std_conv(ctx, file, "block1.conv1", kRootWidth, kRootWidth, 1)),
      conv2_(load_std_conv(ctx, file, "block1.conv2", kRootWidth, kRootWidth, 3, true)),
      conv3_(load_std_conv(ctx, file, "block1.conv3", kRootWidth, kBlockWidth, 1)),
      conv_proj_(load_std_conv(ctx, file, "block1.conv_proj", kRootWidth, kBlockWidth, 1)),
      embedding_(load_embedding(ctx, file, shape_.width)),
      gn_root_(load_norm(ctx, file, "gn_root", kRootWidth)),
      gn1_(load_norm(ctx, file, "block1.gn1", kRootWidth)),
      gn2_(load_norm(ctx, file, "block1.gn2", kRootWidth)),
      gn3_(load_norm(ctx, file, "block1.gn3", kBlockWidth)),
      gn_proj_(load_norm(ctx, file, "block1.gn_proj", kBlockWidth)),
      encoder_norm_(load_norm(ctx, file, kEncoder + "encoder_norm", shape_.width)),
      position_emb_(file.read(kEncoder + "posembed_input.position_emb", {1, shape_.grid * shape_.grid, shape_.width})),
      scale_emb_(file.read(kEncoder + "scaleembed_input.scale_emb", {shape_.scales, shape_.width})),
      cls_(file.read(kEncoder + "cls", {1, 1, shape_.width})),
      head_weight_(file.read("head.weight", {1, shape_.width})),
      head_bias_(file.read("head.bias", {1}).at(0)) {
  for (uint32_t i = 0; i < shape_.depth; ++i) blocks_.push_back(load_block(ctx, file, shape_, i));
}

Tensor MusiqNet::root(const std::vector<float>& pixels, uint32_t first, uint32_t count) const {
  // The mosaic (musiq_net.h): two more zero rows at the bottom make the convolution's output 18 count rows.
  const size_t patch_values = size_t{kPatch} * kPatch;
  const uint32_t height = kMosaicCell * count + 2;
  std::vector<float> mosaic(size_t{3} * height * kMosaicCell, 0.0f);
  for (uint32_t p = 0; p < count; ++p)
    for (uint32_t c = 0; c < 3; ++c)
      for (uint32_t y = 0; y < kPatch; ++y)
        std::copy_n(pixels.begin() + std::ptrdiff_t(((size_t{first} + p) * 3 + c) * patch_values + size_t{y} * kPatch), kPatch,
                    mosaic.begin() + std::ptrdiff_t((size_t{c} * height + kMosaicCell * p + 2 + y) * kMosaicCell + 2));
  engine::Recorder rec(ctx_, "musiq root");
  const Tensor x = upload_tensor(ctx_, "musiq patches", 3, height, kMosaicCell, mosaic);
  const CellWindow conv_cells{kConvCell, 1, kPatch / 2, 1, kPatch / 2}, pool_cells{kPoolCell, 1, kMap, 1, kMap};
  // Convolutions of k > 1 as im2col and a 1x1 convolution (nn_conv_strided's loop per output is slow on lavapipe).
  const uint32_t conv_h = kConvCell * count, conv_w = kConvCell - 1, pool_h = kPoolCell * count;
  const Tensor root = unflat(conv1x1(rec, flat(im2col(rec, x, 7, 2, 2)), conv_root_, false), conv_h, conv_w);
  const Tensor pooled = flat(maxpool3s2(rec, group_norm_cells(rec, root, gn_root_, kGroups, kRootEps, conv_cells, true), 1));
  const auto gn = [&](Tensor t, const NormWeights& w, bool relu) {
    return group_norm_cells(rec, unflat(std::move(t), pool_h, kPoolCell), w, kGroups, kBlockEps, pool_cells, relu);
  };
  const Tensor h1 = gn(conv1x1(rec, pooled, conv1_, false), gn1_, true);
  // The 3x3 too: nn_conv3x3_zero's 32-wide tiles would leave most of a 9-wide cell column idle.
  Tensor h2 = gn(conv1x1(rec, flat(im2col(rec, h1, 3, 1, 1)), conv2_, false), gn2_, true);
  Tensor out = add(rec, gn(conv1x1(rec, flat(std::move(h2)), conv3_, false), gn3_, false), gn(conv1x1(rec, pooled, conv_proj_, false), gn_proj_, false));
  relu_inplace(rec, out);
  Tensor tokens = unflat(conv1x1(rec, flat(im2col(rec, out, kPoolCell, kPoolCell, 0)), embedding_, false), count, 1);
  ctx_.run(std::move(rec));
  return tokens;
}

double MusiqNet::score(const MusiqPatches& patches) const {
  const auto n = static_cast<uint32_t>(patches.position.size());
  const uint32_t d = shape_.width;
  if (n == 0 || patches.scale.size() != n || patches.pixels.size() != size_t{n} * 3 * kPatch * kPatch)
    throw std::invalid_argument("musiq: " + std::to_string(patches.pixels.size()) + " pixel values, " + std::to_string(n) +
                                " positions and " + std::to_string(patches.scale.size()) + " scales do not make whole patches");
  // The class token, then each patch's position and scale embeddings, as one [width, 1, 1 + n] addend.
  std::vector<float> addend(size_t{d} * (1 + n));
  for (uint32_t t = 0; t <= n; ++t) {
    if (t > 0 && (patches.position[t - 1] >= shape_.grid * shape_.grid || patches.scale[t - 1] >= shape_.scales))
      throw std::invalid_argument("musiq: patch " + std::to_string(t - 1) + " has position " +
                                  std::to_string(patches.position[t - 1]) + " or scale " + std::to_string(patches.scale[t - 1]) +
                                  " outside the " + std::to_string(shape_.grid) + "^2 grid and " +
                                  std::to_string(shape_.scales) + " scales");
    for (uint32_t c = 0; c < d; ++c)
      addend[size_t{c} * (1 + n) + t] =
          t == 0 ? cls_[c]
                 : position_emb_[size_t{patches.position[t - 1]} * d + c] + scale_emb_[size_t{patches.scale[t - 1]} * d + c];
  }
  // One chunk's tokens as they are; more chunks' copied channel by channel into one [width, n, 1].
  Tensor embedded = n <= kChunk ? root(patches.pixels, 0, n) : make_tensor(ctx_, "musiq patch tokens", d, n, 1);
  for (uint32_t first = 0; n > kChunk && first < n; first += kChunk) {
    const uint32_t count = std::min(kChunk, n - first);
    const Tensor part = root(patches.pixels, first, count);
    engine::Recorder rec(ctx_, "musiq tokens");
    for (uint32_t c = 0; c < d; ++c)
      rec.copy(part.buffer, embedded.buffer, size_t{count} * sizeof(float), size_t{c} * count * sizeof(float),
               (size_t{c} * n + first) * sizeof(float));
    ctx_.run(std::move(rec));
  }
  engine::Recorder rec(ctx_, "musiq encoder");
  Tensor x = vit_embed(rec, embedded, upload_tensor(ctx_, "musiq embeddings", d, 1, 1 + n, addend));
  for (const TransformerBlock& b : blocks_) x = transformer_block(rec, b, shape_.heads, kNormEps, std::move(x));
  const Tensor y = layernorm(rec, x, encoder_norm_, kNormEps);
  ctx_.run(std::move(rec));
  const std::vector<float> all = download(ctx_, y);
  double score = head_bias_;
  for (uint32_t c = 0; c < d; ++c) score += double(head_weight_[c]) * double(all[size_t{c} * (1 + n)]);
  return score;
}

}  // namespace s4d::nn
