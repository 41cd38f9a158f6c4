// check_frame_content: a camera whose frames decode all black, or all one colour (a video the
// decoder could not really read, a capture with the lens cap on), is a warning naming the camera and
// the frames; training on it would run and learn nothing. A few frames per camera are decoded.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <optional>

#include "dataset_check_parts.h"
#include "s4d/io/image_io.h"
#include "video_decoders.h"

namespace s4d::data::detail {
namespace {

// Within one 8-bit level of each other: one colour, whatever the codec's rounding.
constexpr float kOneColour = 1.5f / 255.0f;
// A video's frames are sampled near its start: reaching its last frame would decode it all.
constexpr int kVideoSpan = 10;

// The image's colour when every pixel has it (within kOneColour per channel); nothing otherwise.
std::optional<std::array<float, 3>> one_colour(const io::ImageF& image) {
  const size_t c = static_cast<size_t>(image.channels), pixels = image.data.size() / std::max<size_t>(1, c);
  if (pixels == 0) return std::nullopt;
  std::array<float, 3> lo{1e9f, 1e9f, 1e9f}, hi{-1e9f, -1e9f, -1e9f};
  for (size_t i = 0; i < pixels; ++i)
    for (size_t k = 0; k < 3; ++k) {
      const float v = image.data[i * c + std::min(k, c - 1)];
      lo[k] = std::min(lo[k], v), hi[k] = std::max(hi[k], v);
    }
  for (size_t k = 0; k < 3; ++k)
    if (hi[k] - lo[k] > kOneColour) return std::nullopt;
  return lo;
}

std::string colour_name(const std::array<float, 3>& c) {
  char text[64];
  std::snprintf(text, sizeof text, "%.2f,%.2f,%.2f", static_cast<double>(c[0]), static_cast<double>(c[1]),
                static_cast<double>(c[2]));
  const float brightest = std::max({c[0], c[1], c[2]});
  return std::string(text) + (brightest <= kOneColour ? " (black)" : "");
}

}  // namespace

void check_frame_content(const Dataset& dataset, Problems& problems) {
  // The views of each physical camera in dataset order; a monocular capture (a camera per view) is one.
  std::vector<std::string> order;
  std::map<std::string, std::vector<const View*>> cameras;
  for (const View& v : dataset.views) {
    const std::string camera = v.camera_index >= 0 ? v.name.substr(0, v.name.find('/')) : "the monocular camera";
    if (cameras[camera].empty()) order.push_back(camera);
    cameras[camera].push_back(&v);
  }
  VideoDecoders videos;
  for (const std::string& camera : order) {
    const std::vector<const View*>& views = cameras[camera];
    const bool video = views.front()->frame_in_file >= 0;
    const size_t last = video ? std::min<size_t>(views.size() - 1, kVideoSpan) : views.size() - 1;
    std::vector<const View*> sampled = {views.front(), views[last / 2], views[last]};
    sampled.erase(std::unique(sampled.begin(), sampled.end()), sampled.end());
    std::optional<std::array<float, 3>> colour;
    std::string frames;
    bool uniform = true;
    for (const View* v : sampled) {
      try {
        const io::ImageF image = video ? videos.read(v->image, v->frame_in_file) : io::read_png(v->image);
        const std::optional<std::array<float, 3>> c = one_colour(image);
        bool same = c.has_value();
        for (size_t k = 0; same && colour && k < 3; ++k) same = std::abs((*c)[k] - (*colour)[k]) <= kOneColour;
        uniform = uniform && same;
        if (c && !colour) colour = c;
      } catch (const std::exception&) {
        uniform = false;  // unreadable frames are check_images' errors
      }
      if (!uniform) break;
      frames += (frames.empty() ? "" : ", ") + v->name;
    }
    if (!uniform || !colour) continue;
    problems.warning(video ? views.front()->image : views.front()->image.parent_path(), "frames",
                     "camera " + camera + ": every frame sampled (" + frames + ") decodes as one colour, " +
                         colour_name(*colour) + "; a video the decoder cannot read, or a capture with no picture? "
                         "Training on it learns nothing");
  }
}

}  // namespace s4d::data::detail
