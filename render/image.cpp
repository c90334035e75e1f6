#include "render/image.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <system_error>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace chainmail::render {

int label_strip_height(int height) {
  return std::clamp(height / 16, 9, 28);
}

std::string panel_label(const Panel& panel) {
  std::string label = panel.label;
  char buffer[96];
  if (panel.frame) {
    std::snprintf(buffer, sizeof(buffer), "  t = %.3f s", panel.frame->t);
    label += buffer;
  }
  if (panel.ms_per_step >= 0.0) {
    std::snprintf(buffer, sizeof(buffer), "  %.3f ms/step", panel.ms_per_step);
    label += buffer;
  }
  return label;
}

void draw_label(Image& image, const std::string& text) {
  // stb_easy_font glyphs are 7 px tall (plus descenders); scale them to the strip
  const int strip = std::min(label_strip_height(image.height), image.height);
  const int scale = std::max(1, strip / 11);
  for (int y = 0; y < strip; ++y) {
    for (int x = 0; x < image.width; ++x) {
      unsigned char* p = &image.rgba[(static_cast<size_t>(y) * image.width + x) * 4];
      for (int c = 0; c < 3; ++c) p[c] = static_cast<unsigned char>(p[c] * 2 / 5);
    }
  }
  // the font's quads are axis aligned: fill them as rectangles
  std::vector<char> buffer(std::max<size_t>(text.size(), 1) * 300 + 1000);
  std::string copy = text;
  const int quads = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, buffer.data(),
                                        static_cast<int>(buffer.size()));
  const int margin_x = 2 * scale, margin_y = std::max(1, (strip - 8 * scale) / 2);
  for (int q = 0; q < quads; ++q) {
    const float* v0 = reinterpret_cast<const float*>(buffer.data() + q * 64);
    const float* v2 = reinterpret_cast<const float*>(buffer.data() + q * 64 + 32);
    const int x0 = margin_x + static_cast<int>(v0[0]) * scale;
    const int y0 = margin_y + static_cast<int>(v0[1]) * scale;
    const int x1 = margin_x + static_cast<int>(v2[0]) * scale;
    const int y1 = margin_y + static_cast<int>(v2[1]) * scale;
    for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y) {
      for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) {
        unsigned char* p = &image.rgba[(static_cast<size_t>(y) * image.width + x) * 4];
        p[0] = p[1] = p[2] = 240;
      }
    }
  }
}

Image compose_horizontal(const std::vector<Image>& panels) {
  Image out;
  for (const Image& panel : panels) {
    out.width += panel.width;
    out.height = std::max(out.height, panel.height);
  }
  out.rgba.assign(static_cast<size_t>(out.width) * out.height * 4, 0);
  int x0 = 0;
  for (const Image& panel : panels) {
    for (int y = 0; y < panel.height; ++y) {
      std::copy_n(&panel.rgba[static_cast<size_t>(y) * panel.width * 4], panel.width * 4,
                  &out.rgba[(static_cast<size_t>(y) * out.width + x0) * 4]);
    }
    x0 += panel.width;
  }
  return out;
}

void write_png(const Image& image, const std::string& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<size_t>(image.width) * image.height * 4) {
    throw RenderError("render: cannot write " + path + ": empty or inconsistent image");
  }
  // write beside the target and rename, so that a crash never leaves half a PNG
  const std::string temporary = path + ".tmp";
  if (!stbi_write_png(temporary.c_str(), image.width, image.height, 4, image.rgba.data(),
                      image.width * 4)) {
    std::remove(temporary.c_str());
    throw RenderError("render: cannot write " + temporary);
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::remove(temporary.c_str());
    throw RenderError("render: cannot rename " + temporary + " to " + path + ": " +
                      error.message());
  }
}

}  // namespace chainmail::render
