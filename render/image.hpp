// CPU image helpers of the renderer: panel labels (stb_easy_font), side-by-side composition.
#pragma once

#include <string>
#include <vector>

#include "render/types.hpp"

namespace chainmail::render {

// height of the label strip for an image `height` pixels tall
int label_strip_height(int height);
// darkens a strip at the top of `image` and writes `text` into it in white
void draw_label(Image& image, const std::string& text);
// a panel's label text: its name, then the frame's time and the backend's ms per step when known
std::string panel_label(const Panel& panel);
// panels of equal height, left to right
Image compose_horizontal(const std::vector<Image>& panels);

// PNG through stb_image_write, written to PATH.tmp then renamed; throws RenderError
void write_png(const Image& image, const std::string& path);

}  // namespace chainmail::render
