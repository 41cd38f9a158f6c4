// OpenEXR through the C++ API of OpenEXR 3. Writing goes into memory (an Imf::OStream over a
// string) and then through the atomic replace; OpenEXR's own exceptions (Iex, std) are turned into
// std::runtime_error naming the file.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cstring>
#include <set>
#include <stdexcept>

#include "file_read.h"
#include "s4d/io/image_io.h"
#include "s4d/util/atomic_file.h"

namespace s4d::io {
namespace {

// An in-memory output file. OutputFile seeks back to fill in the line offset table, so writes
// may overwrite earlier bytes as well as append.
class StringOStream : public Imf::OStream {
 public:
  explicit StringOStream(const std::string& name) : Imf::OStream(name.c_str()) {}

  void write(const char c[], int n) override {
    const size_t count = static_cast<size_t>(n);
    if (pos_ + count > bytes_.size()) bytes_.resize(pos_ + count);
    std::memcpy(bytes_.data() + pos_, c, count);
    pos_ += count;
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = pos; }

  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  uint64_t pos_ = 0;
};

}  // namespace

void write_exr(const std::filesystem::path& path, int width, int height,
               const std::vector<std::pair<std::string, const float*>>& channels) {
  if (width < 1 || height < 1) {
    throw std::invalid_argument("write_exr: bad size " + std::to_string(width) + "x" + std::to_string(height));
  }
  if (channels.empty()) throw std::invalid_argument("write_exr: no channels");
  std::set<std::string> names;
  for (const auto& [name, values] : channels) {
    if (name.empty() || !values) throw std::invalid_argument("write_exr: channel with an empty name or no data");
    if (!names.insert(name).second) throw std::invalid_argument("write_exr: channel '" + name + "' given twice");
  }

  StringOStream stream(path.string());
  try {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame_buffer;
    const size_t row_stride = sizeof(float) * static_cast<size_t>(width);
    for (const auto& [name, values] : channels) {
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      frame_buffer.insert(
          name, Imf::Slice::Make(Imf::FLOAT, values, Imath::V2i(0, 0), width, height, sizeof(float), row_stride));
    }
    // The file is complete only once OutputFile is destroyed (it writes the offset table then).
    Imf::OutputFile file(stream, header);
    file.setFrameBuffer(frame_buffer);
    file.writePixels(height);
  } catch (const std::exception& e) {
    detail::fail(path, std::string("cannot encode EXR: ") + e.what());
  }
  util::write_file_atomic(path, stream.bytes());
}

ExrImage read_exr(const std::filesystem::path& path) {
  // Opened here first so a missing file gets the same message as every other reader.
  detail::open_for_reading(path);
  ExrImage image;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    const size_t count = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    Imf::FrameBuffer frame_buffer;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
      std::vector<float>& values = image.channels[it.name()];
      values.resize(count);
      // Half and uint channels are converted to float by the library.
      frame_buffer.insert(it.name(), Imf::Slice::Make(Imf::FLOAT, values.data(), window, sizeof(float),
                                                      sizeof(float) * static_cast<size_t>(image.width)));
    }
    file.setFrameBuffer(frame_buffer);
    file.readPixels(window.min.y, window.max.y);
  } catch (const std::exception& e) {
    detail::fail(path, std::string("cannot read EXR: ") + e.what());
  }
  return image;
}

}  // namespace s4d::io
