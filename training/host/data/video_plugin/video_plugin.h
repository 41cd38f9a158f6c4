// The interface between the program and its video plugin, libs4d_video.so: OpenCV's videoio,
// with FFmpeg and 229 shared libraries on Debian 12 behind it, lives only in the plugin, which the
// program opens on its first video (video_plugin_loader.cpp). A run that never reads or writes a
// video never loads FFmpeg, and the release runs without it (docs/release.md). Plugin and program
// come from one build, so the interface is plain C++; kAbiVersion still refuses a plugin from
// another build.
#pragma once
#include <opencv2/core.hpp>

namespace s4d::data::video_plugin {

inline constexpr int kAbiVersion = 1;
inline constexpr const char* kLibraryName = "libs4d_video.so";
inline constexpr const char* kEntryPoint = "s4d_video_plugin_api";

// An open decoder (cv::VideoCapture with the FFmpeg backend).
class Capture {
 public:
  virtual ~Capture() = default;
  // What the container declares, as OpenCV reports it: 0 when unknown.
  virtual double width() const = 0;
  virtual double height() const = 0;
  virtual double frame_count() const = 0;
  virtual bool read(cv::Mat& bgr) = 0;  // decodes the next frame; false at the end
  virtual bool grab() = 0;              // skips the next frame
  virtual bool seek(int frame) = 0;     // the next read() decodes `frame`
};

// An open mp4v encoder (cv::VideoWriter with the FFmpeg backend); the destructor finishes the file.
class Encoder {
 public:
  virtual ~Encoder() = default;
  virtual void write(const cv::Mat& bgr) = 0;  // 8-bit BGR at the encoder's size
};

struct Api {
  int abi_version;
  // Each returns a new object the caller deletes, or nullptr when OpenCV cannot open the file.
  Capture* (*open_capture)(const char* path);
  Encoder* (*open_encoder)(const char* path, double fps, int width, int height);
};

// The plugin's table, the plugin opened on the first call. Throws std::runtime_error
// "<for_path>: ..." when it cannot be loaded (missing, or from another build).
const Api& api(const char* for_path);

}  // namespace s4d::data::video_plugin

// The plugin's one exported symbol (the plugin builds with hidden visibility).
extern "C" __attribute__((visibility("default"))) const s4d::data::video_plugin::Api* s4d_video_plugin_api();
