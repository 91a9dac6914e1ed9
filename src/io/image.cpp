#include "io/image.h"

#include <png.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/temp_files.h"

namespace nsf {

namespace fs = std::filesystem;

Image::Image(int w, int h, Rgb fill) : width(w), height(h) {
  if (w < 0 || h < 0) fail("image size ", w, "x", h, " is negative");
  rgb.resize(3 * static_cast<size_t>(w) * h);
  for (size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = fill.r;
    rgb[i + 1] = fill.g;
    rgb[i + 2] = fill.b;
  }
}

// libpng's simplified API reports errors through png_image::message instead of longjmp, which
// would skip C++ destructors.
void write_png(const Image& img, const std::string& path) {
  if (img.width <= 0 || img.height <= 0) {
    fail(path, ": cannot write an empty ", img.width, "x", img.height, " image");
  }
  if (img.rgb.size() != 3 * static_cast<size_t>(img.width) * img.height) {
    fail(path, ": image buffer does not match its ", img.width, "x", img.height, " size");
  }
  const std::string tmp = path + ".tmp";
  FILE* file = ::fdopen(create_exclusive(tmp, path), "wb");  // never through a link at tmp
  if (!file) fail(path, ": cannot open ", tmp, " for writing");
  const TempFileRegistration registration(tmp);  // a fatal signal deletes it
  png_image pi;
  std::memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  pi.width = static_cast<png_uint_32>(img.width);
  pi.height = static_cast<png_uint_32>(img.height);
  pi.format = PNG_FORMAT_RGB;
  const bool written = png_image_write_to_stdio(&pi, file, 0, img.rgb.data(), 0, nullptr) != 0;
  const bool closed = std::fclose(file) == 0;  // flushes: a full disk or a size limit shows here
  if (!written || !closed) {
    const std::string msg = written ? std::string("write failed (disk full?)") : pi.message;
    png_image_free(&pi);
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fail(path, ": cannot write PNG: ", msg);
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    fail(path, ": cannot move ", tmp, " into place: ", ec.message());
  }
}

Image read_png(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail(path, ": no such file");
  png_image pi;
  std::memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&pi, path.c_str())) {
    const std::string msg = pi.message;
    png_image_free(&pi);
    fail(path, ": not a readable PNG: ", msg);
  }
  pi.format = PNG_FORMAT_RGB;
  Image img(static_cast<int>(pi.width), static_cast<int>(pi.height));
  png_color white{255, 255, 255};  // what transparent pixels become
  if (!png_image_finish_read(&pi, &white, img.rgb.data(), 0, nullptr)) {
    const std::string msg = pi.message;
    png_image_free(&pi);
    fail(path, ": damaged PNG: ", msg);
  }
  return img;
}

Image side_by_side(const Image& a, const Image& b, int gap, Rgb fill) {
  gap = std::max(gap, 0);
  Image out(a.width + gap + b.width, std::max(a.height, b.height), fill);
  const auto blit = [&](const Image& src, int x0) {
    for (int y = 0; y < src.height; ++y) {
      std::memcpy(out.rgb.data() + 3 * (static_cast<size_t>(y) * out.width + x0),
                  src.rgb.data() + 3 * static_cast<size_t>(y) * src.width, 3 * src.width);
    }
  };
  blit(a, 0);
  blit(b, a.width + gap);
  return out;
}

Image above_below(const Image& a, const Image& b, int gap, Rgb fill) {
  gap = std::max(gap, 0);
  Image out(std::max(a.width, b.width), a.height + gap + b.height, fill);
  const auto blit = [&](const Image& src, int y0) {
    for (int y = 0; y < src.height; ++y)
      std::memcpy(out.rgb.data() + 3 * (static_cast<size_t>(y0 + y) * out.width),
                  src.rgb.data() + 3 * static_cast<size_t>(y) * src.width, 3 * src.width);
  };
  blit(a, 0);
  blit(b, a.height + gap);
  return out;
}

}  // namespace nsf
