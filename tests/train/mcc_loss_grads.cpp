// The MCCNet loss (s4d/nn/mcc_loss.h) of one content/style pair and its gradients w.r.t. the decoder
// and MCC parameters, for mcc_loss_reference.py to compare with its PyTorch reference. DIR holds
// vgg.safetensors, decoder.safetensors, mcc.safetensors (the state-dict names the hgst stylizer
// reads) and inputs.safetensors ("content", "style", "content_noise": [3, H, W]). Prints one JSON object:
// {"loss": {"content": .., "style": .., "identity1": .., "identity2": .., "noise": .., "tv": .., "selfsim": .., "total": ..},
//  "grads": {"decoder.<prefix>.weight": [...], ..., "MCCN.f.bias": [...], ...}}.
//   mcc_loss_grads DIR W1 W2 W3 W4 W5 CONTENT_WEIGHT STYLE_WEIGHT IDENTITY1_WEIGHT IDENTITY2_WEIGHT NOISE_WEIGHT TV_WEIGHT SELFSIM_WEIGHT mccnet|hgst
// (the content and style levels, nn::MccLossLevels).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/nn/mcc_loss.h"

namespace {

using namespace s4d;

void print_array(const std::vector<float>& v) {
  std::printf("[");
  for (size_t k = 0; k < v.size(); ++k) std::printf("%s%.9g", k ? "," : "", double(v[k]));
  std::printf("]");
}

nn::Tensor read_image(engine::Context& ctx, const io::SafetensorsFile& file, const std::string& name) {
  const auto& shape = file.shape(name);
  if (shape.size() != 3 || shape[0] != 3) throw std::runtime_error(name + " is not [3, H, W]");
  const auto h = static_cast<uint32_t>(shape[1]), w = static_cast<uint32_t>(shape[2]);
  return nn::upload_tensor(ctx, name, 3, h, w, file.read(name, shape));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 15 || (std::string(argv[14]) != "mccnet" && std::string(argv[14]) != "hgst")) {
    std::fprintf(stderr, "usage: mcc_loss_grads DIR W1 W2 W3 W4 W5 CONTENT STYLE IDENTITY1 IDENTITY2 NOISE TV SELFSIM mccnet|hgst\n");
    return 2;
  }
  try {
    const std::string dir = argv[1];
    nn::VggWidths widths;
    for (int l = 0; l < 5; ++l) widths.level[l] = static_cast<uint32_t>(std::atoi(argv[2 + l]));
    const nn::MccLossWeights weights{std::strtof(argv[7], nullptr), std::strtof(argv[8], nullptr),
                                     std::strtof(argv[9], nullptr), std::strtof(argv[10], nullptr),
                                     std::strtof(argv[11], nullptr), std::strtof(argv[12], nullptr),
                                     std::strtof(argv[13], nullptr)};
    const nn::MccLossLevels levels = std::string(argv[14]) == "hgst" ? nn::MccLossLevels::hgst() : nn::MccLossLevels::mccnet();
    engine::Context ctx;  // ContextOptions::from_env(): S4D_VALIDATION, the device choice
    const nn::VggEncoder encoder(ctx, io::SafetensorsFile(dir + "/vgg.safetensors"), 5, widths);
    const nn::VggDecoder decoder(ctx, io::SafetensorsFile(dir + "/decoder.safetensors"), widths);
    const nn::MccModule mcc(ctx, io::SafetensorsFile(dir + "/mcc.safetensors"), widths.level[3]);
    const io::SafetensorsFile inputs(dir + "/inputs.safetensors");
    const nn::Tensor content = read_image(ctx, inputs, "content"), style = read_image(ctx, inputs, "style");
    const nn::Tensor content_noise = read_image(ctx, inputs, "content_noise");
    const nn::MccTrainee net{encoder, decoder, mcc};
    engine::Recorder rec(ctx, "mcc loss");
    nn::MccGrads grads = nn::zero_mcc_grads(rec, net);
    const nn::MccLossRecord record = nn::record_mcc_loss(rec, net, content, style, content_noise, levels, weights, grads);
    ctx.run(std::move(rec));
    const nn::MccLossValues v = record.values(ctx, weights);
    std::printf("{\"loss\": {\"content\": %.9g, \"style\": %.9g, \"identity1\": %.9g, \"identity2\": %.9g, "
                "\"noise\": %.9g, \"tv\": %.9g, \"selfsim\": %.9g, \"total\": %.9g},\n",
                v.content, v.style, v.identity1, v.identity2, v.noise, v.tv, v.selfsim, v.total);
    std::printf("\"grads\": {");
    bool first = true;
    auto print_grads = [&](const std::string& name, const nn::ConvWeights& w, const nn::ConvGrads& g) {
      std::printf("%s\"%s.weight\": ", first ? "" : ",\n", name.c_str());
      print_array(ctx.download<float>(g.weight, w.weight.size() / sizeof(float)));
      std::printf(",\n\"%s.bias\": ", name.c_str());
      print_array(ctx.download<float>(g.bias, w.bias.size() / sizeof(float)));
      first = false;
    };
    const auto dec = decoder.parameters();
    for (size_t i = 0; i < dec.size(); ++i) print_grads("decoder." + dec[i].first, *dec[i].second, grads.decoder[i]);
    const auto m = mcc.parameters();
    for (size_t i = 0; i < m.size(); ++i) print_grads(m[i].first, *m[i].second, grads.mcc[i]);
    std::printf("}}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcc_loss_grads: %s\n", e.what());
    return 1;
  }
  return 0;
}
