// s4d_contact_sheet --content DIR --styles DIR --out F.png [--work N] [--cell N] [--stylizer NAME]:
// a grid that shows what a stylizer does to every content picture with every style. The top row
// holds the styles, the left column the contents, and cell (content, style) the result. Inputs are
// shrunk to N pixels on the long side before stylizing (default 256), cells to --cell (default 160).
// Developer tool behind tools/make_contact_sheet.sh; docs/stylizer_contact_sheet.png is its output.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "s4d/io/image_io.h"
#include "s4d/io/image_file.h"
#include "s4d/frame_stylizers/registry.h"

namespace fs = std::filesystem;
using s4d::io::ImageF;

namespace {

std::vector<fs::path> pictures(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) out.push_back(e.path());
  }
  if (out.empty()) throw std::runtime_error(dir.string() + ": no PNG or JPEG pictures");
  std::sort(out.begin(), out.end());
  return out;
}

// The picture shrunk (or grown) to `side` pixels on its long side, aspect kept, sides even.
ImageF fit(const ImageF& image, int side) {
  const double s = static_cast<double>(side) / std::max(image.width, image.height);
  const int w = std::max(2, 2 * static_cast<int>(image.width * s / 2)), h = std::max(2, 2 * static_cast<int>(image.height * s / 2));
  return s4d::io::resize_image(image, w, h);
}

// Pastes `image`, fitted into a cell x cell square, centred in the cell at column cx, row cy.
void paste(ImageF& sheet, const ImageF& image, int cx, int cy, int cell, int gap) {
  const ImageF f = fit(image, cell);
  const int x0 = gap + cx * (cell + gap) + (cell - f.width) / 2, y0 = gap + cy * (cell + gap) + (cell - f.height) / 2;
  for (int y = 0; y < f.height; ++y)
    std::copy_n(&f.data[static_cast<size_t>(y) * f.width * 3], f.width * 3,
                &sheet.data[(static_cast<size_t>(y0 + y) * sheet.width + x0) * 3]);
}

std::string value(const std::vector<std::string>& args, const std::string& name, const std::string& fallback) {
  for (size_t i = 0; i + 1 < args.size(); ++i)
    if (args[i] == "--" + name) return args[i + 1];
  if (fallback.empty()) throw std::invalid_argument("missing --" + name);
  return fallback;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    const auto contents = pictures(value(args, "content", "")), styles = pictures(value(args, "styles", ""));
    const fs::path out = value(args, "out", "");
    const int work = std::stoi(value(args, "work", "256")), cell = std::stoi(value(args, "cell", "160")), gap = 4;
    const auto stylizer = s4d::frame_stylizers::make_stylizer(value(args, "stylizer", "patch"));

    const int cols = static_cast<int>(styles.size()) + 1, rows = static_cast<int>(contents.size()) + 1;
    ImageF sheet{gap + cols * (cell + gap), gap + rows * (cell + gap), 3, {}};
    sheet.data.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 0.12f);
    std::vector<ImageF> style_images;
    for (size_t s = 0; s < styles.size(); ++s) {
      style_images.push_back(fit(s4d::io::read_image_rgb(styles[s]), work));
      paste(sheet, style_images.back(), static_cast<int>(s) + 1, 0, cell, gap);
    }
    for (size_t c = 0; c < contents.size(); ++c) {
      const ImageF content = fit(s4d::io::read_image_rgb(contents[c]), work);
      paste(sheet, content, 0, static_cast<int>(c) + 1, cell, gap);
      for (size_t s = 0; s < styles.size(); ++s) {
        std::cerr << contents[c].filename().string() << " x " << styles[s].filename().string() << "\n";
        const ImageF result = stylizer->stylize({content}, style_images[s], {})[0];
        paste(sheet, result, static_cast<int>(s) + 1, static_cast<int>(c) + 1, cell, gap);
      }
    }
    s4d::io::write_png(out, sheet);
    std::cout << "wrote " << out.string() << " (" << contents.size() << " contents x " << styles.size() << " styles)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "s4d_contact_sheet: error: " << e.what() << "\n";
    return 1;
  }
}
