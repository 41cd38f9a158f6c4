// The MCCNet loss (s4d/nn/mcc_loss.h) of one content/style pair and its gradients w.r.t. the decoder
// and MCC parameters, for mcc_loss_reference.py to compare with its PyTorch reference. DIR holds
// vgg.safetensors, decoder.safetensors, mcc.safetensors (the state-dict names the hgst stylizer
// reads) and inputs.safetensors ("content", "style", "content_noise": [3, H, W]; per CCPL level l
// "ccpl.<l>.anchor" and "ccpl.<l>.neighbour", the sampled flat indices as floats), and with CCPL
// levels heads.safetensors ("ccpl_heads.<l>.0" Linear(C, C), "ccpl_heads.<l>.2" Linear(C, C / 4)).
// Prints one JSON object:
// {"loss": {"content": .., "style": .., "identity1": .., "identity2": .., "noise": .., "tv": .., "selfsim": .., "ccpl": .., "total": ..},
//  "grads": {"decoder.<prefix>.weight": [...], ..., "MCCN.f.bias": [...], ..., "ccpl_heads.<l>.0.weight": [...] (TRAIN_HEADS 1)}}.
//   mcc_loss_grads DIR W1 W2 W3 W4 W5 CONTENT STYLE IDENTITY1 IDENTITY2 NOISE TV SELFSIM CCPL mccnet|hgst LEVELS 0|1
// (the content and style levels, nn::MccLossLevels; LEVELS the CCPL levels as "3,4", or "-" for none;
// 1: the heads' gradients through q and k, as CCPL trains them).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "s4d/engine/context.h"
#include "s4d/nn/mcc_loss.h"
#include "s4d/nn/weights.h"

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
  if (argc != 18 || (std::string(argv[15]) != "mccnet" && std::string(argv[15]) != "hgst")) {
    std::fprintf(stderr, "usage: mcc_loss_grads DIR W1 W2 W3 W4 W5 CONTENT STYLE IDENTITY1 IDENTITY2 NOISE TV SELFSIM CCPL mccnet|hgst LEVELS 0|1\n");
    return 2;
  }
  try {
    const std::string dir = argv[1];
    nn::VggWidths widths;
    for (int l = 0; l < 5; ++l) widths.level[l] = static_cast<uint32_t>(std::atoi(argv[2 + l]));
    const nn::MccLossWeights weights{std::strtof(argv[7], nullptr), std::strtof(argv[8], nullptr),
                                     std::strtof(argv[9], nullptr), std::strtof(argv[10], nullptr),
                                     std::strtof(argv[11], nullptr), std::strtof(argv[12], nullptr),
                                     std::strtof(argv[13], nullptr), std::strtof(argv[14], nullptr)};
    const nn::MccLossLevels levels = std::string(argv[15]) == "hgst" ? nn::MccLossLevels::hgst() : nn::MccLossLevels::mccnet();
    nn::MccCcplInputs ccpl;
    for (const char* c = argv[16]; *c != '\0' && *c != '-'; ++c)
      if (*c != ',') ccpl.config.levels.push_back(*c - '0');
    ccpl.config.train_heads = std::string(argv[17]) == "1";
    engine::Context ctx;  // ContextOptions::from_env(): S4D_VALIDATION, the device choice
    const nn::VggEncoder encoder(ctx, io::SafetensorsFile(dir + "/vgg.safetensors"), 5, widths);
    const nn::VggDecoder decoder(ctx, io::SafetensorsFile(dir + "/decoder.safetensors"), widths);
    const nn::MccModule mcc(ctx, io::SafetensorsFile(dir + "/mcc.safetensors"), widths.level[3]);
    const io::SafetensorsFile inputs(dir + "/inputs.safetensors");
    const nn::Tensor content = read_image(ctx, inputs, "content"), style = read_image(ctx, inputs, "style");
    const nn::Tensor content_noise = read_image(ctx, inputs, "content_noise");
    const nn::MccTrainee net{encoder, decoder, mcc};
    std::vector<nn::CcplHead> heads;
    for (const int l : ccpl.config.levels) {
      const io::SafetensorsFile file(dir + "/heads.safetensors");
      const std::string prefix = "ccpl_heads." + std::to_string(l);
      const auto c = static_cast<uint32_t>(widths.level[l - 1]);
      heads.push_back({nn::load_linear(ctx, file, prefix + ".0", c, c), nn::load_linear(ctx, file, prefix + ".2", c, c / 4)});
      nn::CcplSamples samples;
      for (const auto& [name, into] : {std::pair{".anchor", &samples.anchor}, std::pair{".neighbour", &samples.neighbour}})
        for (const float v : inputs.read("ccpl." + std::to_string(l) + name, inputs.shape("ccpl." + std::to_string(l) + name)))
          into->push_back(static_cast<uint32_t>(v));
      ccpl.samples.push_back(std::move(samples));
    }
    if (!heads.empty()) ccpl.heads = &heads;
    engine::Recorder rec(ctx, "mcc loss");
    nn::MccGrads grads = nn::zero_mcc_grads(rec, net);
    std::vector<nn::ConvGrads> head_grads;
    if (ccpl.config.train_heads) {
      for (const nn::CcplHead& h : heads)
        for (const nn::ConvWeights* w : {&h.first, &h.second}) head_grads.push_back(nn::zero_conv_grads(rec, *w));
      ccpl.head_grads = &head_grads;
    }
    const nn::MccLossRecord record = nn::record_mcc_loss(rec, net, content, style, content_noise, levels, weights, ccpl, grads);
    ctx.run(std::move(rec));
    const nn::MccLossValues v = record.values(ctx, weights);
    std::printf("{\"loss\": {\"content\": %.9g, \"style\": %.9g, \"identity1\": %.9g, \"identity2\": %.9g, "
                "\"noise\": %.9g, \"tv\": %.9g, \"selfsim\": %.9g, \"ccpl\": %.9g, \"total\": %.9g},\n",
                v.content, v.style, v.identity1, v.identity2, v.noise, v.tv, v.selfsim, v.ccpl, v.total);
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
    for (size_t i = 0; i < head_grads.size(); ++i) {
      const nn::ConvWeights& w = i % 2 == 0 ? heads[i / 2].first : heads[i / 2].second;
      print_grads("ccpl_heads." + std::to_string(ccpl.config.levels[i / 2]) + (i % 2 == 0 ? ".0" : ".2"), w, head_grads[i]);
    }
    std::printf("}}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcc_loss_grads: %s\n", e.what());
    return 1;
  }
  return 0;
}
