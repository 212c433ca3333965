// Loading and encoding images with OpenCV (PRIVATE to this engine), the gray → RGB overlay base and
// the Gaussian pre-filter.
#include "tricot/image/image.hpp"

#include <algorithm>
#include <iterator>
#include <cmath>
#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "mirror.hpp"
#include "tricot/core/error.hpp"

namespace tricot::image {

namespace {

FileError file_error(const std::filesystem::path& path, const std::string& problem, const std::string& got = {},
                     const std::string& expected = {}) {
  return FileError(Location{path.string(), 0, ""}, problem, got, expected);
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

LoadedImage load_image(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw file_error(path, "image not found");
  if (std::filesystem::is_directory(path, ec)) throw file_error(path, "is a folder, not an image");
  {
    std::ifstream in(path, std::ios::binary);
    char head[8] = {};
    in.read(head, 8);
    const auto n = static_cast<std::size_t>(in.gcount());
    const auto starts = [&](const char* magic, std::size_t len) {
      return n >= len && std::memcmp(head, magic, len) == 0;
    };
    // Only the camera formats reach OpenCV: its other decoders (DICOM through GDCM, HDR, JPEG 2000, …)
    // pick files by signature and some abort the process on a malformed one (GDCM asserts: found by
    // the image fuzzer, issue 14).
    const bool known = starts("\x89PNG\r\n\x1a\n", 8) || starts("II*\0", 4) || starts("MM\0*", 4) ||
                       starts("II+\0", 4) || starts("MM\0+", 4) || starts("BM", 2) || starts("\xff\xd8\xff", 3) ||
                       (n >= 2 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6');
    if (!known) {
      std::string bytes;
      for (std::size_t i = 0; i < n; ++i) bytes += (i ? " " : "") + std::to_string(static_cast<unsigned char>(head[i]));
      throw file_error(path, "cannot decode image",
                       "not a TIFF, PNG, BMP, JPEG or PNM file (first bytes " + bytes + ")",
                       "an 8- or 16-bit TIFF, PNG or BMP");
    }
    // A truncated PNG makes libpng print its own "libpng error" on stderr before OpenCV gives up: find
    // it here instead, from the signature and the closing IEND chunk (issue 14: one error line).
    if (starts("\x89PNG\r\n\x1a\n", 8)) {
      char tail[8] = {};
      in.seekg(-8, std::ios::end);
      in.read(tail, 8);
      if (!in || std::memcmp(tail, "IEND\xae\x42\x60\x82", 8) != 0)
        throw file_error(path, "truncated or corrupt PNG (no IEND chunk at its end)", {}, "a complete PNG file");
    }
  }
  cv::Mat m;
  try {
    m = cv::imread(path.string(), cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
  } catch (const cv::Exception& e) {
    throw file_error(path, "cannot decode image", e.what());
  }
  if (m.empty()) throw file_error(path, "cannot decode image", {}, "an 8- or 16-bit TIFF, PNG or BMP");
  LoadedImage out;
  if (m.channels() == 4) {
    cv::cvtColor(m, m, cv::COLOR_BGRA2GRAY);
    out.was_colour = true;
  } else if (m.channels() == 3) {
    cv::cvtColor(m, m, cv::COLOR_BGR2GRAY);
    out.was_colour = true;
  } else if (m.channels() != 1) {
    throw file_error(path, "unsupported number of channels", std::to_string(m.channels()), "1, 3 or 4");
  }
  if (out.was_colour) out.warning = path.string() + ": colour image converted to gray";
  // The pixel types read, their bits and the value of white.
  struct PixelType {
    int depth, bits;
    double white;
  };
  constexpr PixelType kTypes[] = {
      {CV_8U, 8, 255.0}, {CV_8S, 8, 127.0}, {CV_16U, 16, 65535.0}, {CV_16S, 16, 32767.0}, {CV_32F, 32, 1.0}};
  const auto type =
      std::find_if(std::begin(kTypes), std::end(kTypes), [&](const PixelType& t) { return t.depth == m.depth(); });
  if (type == std::end(kTypes))
    throw file_error(path, "unsupported pixel type", std::to_string(m.depth()), "8- or 16-bit integer or float");
  out.bit_depth = type->bits;
  const double white = type->white;
  cv::Mat f;
  m.convertTo(f, CV_32F);
  out.image = Image(f.cols, f.rows, 0.0f, white);
  for (int y = 0; y < f.rows; ++y)
    std::copy_n(f.ptr<float>(y), f.cols, out.image.pixels.data() + std::size_t(y) * f.cols);
  for (float v : out.image.pixels)
    if (!std::isfinite(v)) throw file_error(path, "image has a pixel that is not a finite number");
  return out;
}

void require_same_size(const Image& reference, const Image& img, const std::filesystem::path& path) {
  if (img.width != reference.width || img.height != reference.height)
    throw file_error(path, "image size differs from the reference image", size_text(img.width, img.height),
                     size_text(reference.width, reference.height));
}

std::string encode_gray(const Image& img, const std::string& extension, int bits) {
  const double top = bits == 16 ? 65535.0 : 255.0;
  const double scale = top / (img.full_scale > 0 ? img.full_scale : 1.0);
  cv::Mat m(img.height, img.width, bits == 16 ? CV_16U : CV_8U);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double v = std::clamp(std::round(img.at(x, y) * scale), 0.0, top);
      if (bits == 16) m.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>(v);
      else m.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(v);
    }
  std::vector<uchar> buf;
  if (!cv::imencode(extension, m, buf)) throw std::runtime_error("cannot encode image as " + extension);
  return std::string(buf.begin(), buf.end());
}

std::string encode_png(const RgbImage& img) {
  cv::Mat m(img.height, img.width, CV_8UC3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = &img.rgb[3 * (std::size_t(y) * img.width + x)];
      m.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);  // OpenCV stores BGR
    }
  std::vector<uchar> buf;
  if (!cv::imencode(".png", m, buf)) throw std::runtime_error("cannot encode PNG");
  return std::string(buf.begin(), buf.end());
}

RgbImage to_rgb(const Image& img, double brightness) {
  RgbImage out(img.width, img.height);
  if (img.empty()) return out;
  std::vector<float> sorted = img.pixels;
  const std::size_t n = sorted.size();
  std::nth_element(sorted.begin(), sorted.begin() + n / 200, sorted.end());
  const float lo = sorted[n / 200];
  std::nth_element(sorted.begin(), sorted.begin() + (n - 1 - n / 200), sorted.end());
  const float hi = sorted[n - 1 - n / 200];
  const double span = hi > lo ? hi - lo : 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double g = std::clamp((img.pixels[i] - lo) / span, 0.0, 1.0) * 255.0 * brightness;
    out.rgb[3 * i] = out.rgb[3 * i + 1] = out.rgb[3 * i + 2] = static_cast<std::uint8_t>(g);
  }
  return out;
}

Image gaussian_blur(const Image& img, double sigma) {
  if (sigma <= 0 || img.empty()) return img;
  const int r = static_cast<int>(std::ceil(3.5 * sigma));
  std::vector<float> k(2 * r + 1);
  double sum = 0;
  for (int i = -r; i <= r; ++i) sum += k[i + r] = static_cast<float>(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (auto& v : k) v = static_cast<float>(v / sum);
  Image tmp(img.width, img.height, 0.0f, img.full_scale), out(img.width, img.height, 0.0f, img.full_scale);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * img.at(detail::mirror(x + i, img.width), y);
      tmp.at(x, y) = s;
    }
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      float s = 0;
      for (int i = -r; i <= r; ++i) s += k[i + r] * tmp.at(x, detail::mirror(y + i, img.height));
      out.at(x, y) = s;
    }
  return out;
}

}  // namespace tricot::image
