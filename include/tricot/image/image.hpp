// Grayscale images for digital image correlation (docs/theory.md §10, docs/design.md).
// Pixels are stored as float, row-major, y down, whatever the bit depth of the file; `full_scale` keeps
// the white level of the source (255, 65535, 1) so that thresholds can be given as fractions of it.
// OpenCV is used for decoding and encoding only and never appears in a public header.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace tricot::image {

/// A grayscale image: `width × height` floats, row-major, pixel (x, y) at `pixels[y * width + x]`,
/// x to the right and y down. Pixel centres are at integer coordinates.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
  /// The white level of the source: 255 for 8-bit, 65535 for 16-bit, 1 for float images.
  double full_scale = 1.0;

  Image() = default;
  Image(int w, int h, float fill = 0.0f, double white = 1.0)
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill),
        full_scale(white) {}

  bool empty() const { return width <= 0 || height <= 0; }
  float at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  float& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const float* row(int y) const { return pixels.data() + static_cast<std::size_t>(y) * width; }
};

/// What load_image found besides the pixels.
struct LoadedImage {
  Image image;
  int bit_depth = 8;        ///< 8, 16 or 32 (float)
  bool was_colour = false;  ///< the file had colour channels; they were converted to gray (a warning)
  std::string warning;      ///< "" or one line for the user, e.g. the colour conversion
};

/// Loads an 8- or 16-bit (or float) grayscale TIFF, PNG or BMP. Colour images are converted to gray
/// (ITU-R BT.601 weights) and flagged in the result. Throws FileError naming the file when it is
/// missing, cannot be decoded or is empty.
LoadedImage load_image(const std::filesystem::path& path);

/// Throws FileError naming `path` when `img` does not have the size of `reference`.
void require_same_size(const Image& reference, const Image& img, const std::filesystem::path& path);

/// Encodes a gray image as 8- or 16-bit PNG/TIFF/BMP bytes (by `extension`: ".png", ".tif", ".bmp").
/// Values are scaled by (2^bits − 1) / full_scale, rounded and clamped.
std::string encode_gray(const Image& img, const std::string& extension, int bits = 8);

/// An 8-bit RGB picture for overlays: `rgb[3 * (y * width + x) + c]`, c = 0 red, 1 green, 2 blue.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
  RgbImage() = default;
  RgbImage(int w, int h) : width(w), height(h), rgb(3 * static_cast<std::size_t>(w) * h, 0) {}
};

/// Encodes an RGB picture as PNG bytes (write them with io::write_atomic).
std::string encode_png(const RgbImage& img);

/// The gray image as an RGB picture, contrast stretched to its 0.5–99.5 % percentiles and dimmed by
/// `brightness` (0–1) so that coloured marks drawn over it stand out.
RgbImage to_rgb(const Image& img, double brightness = 0.6);

/// A separable Gaussian blur with standard deviation `sigma` px (mirror boundaries); `sigma` ≤ 0
/// returns the image unchanged. Used as the DIC pre-filter that reduces the noise-induced bias of
/// sub-pixel interpolation (Pan 2013, doi:10.1088/0957-0233/24/3/035401).
Image gaussian_blur(const Image& img, double sigma);

}  // namespace tricot::image
