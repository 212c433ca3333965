#include "tricot/image/image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"

using namespace tricot;
using namespace tricot::image;

namespace {

Image ramp(int w, int h, double white) {
  Image img(w, h, 0.0f, white);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y) = static_cast<float>(std::round((x + 3 * y) * white / (w + 3 * h)));
  return img;
}

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

std::string message_of(const std::filesystem::path& p) {
  try {
    load_image(p);
  } catch (const FileError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(LoadImage, Reads8BitPngExactly) {
  const auto dir = test::scratch_dir("image_png8");
  const Image img = ramp(40, 30, 255);
  write_bytes(dir / "a.png", encode_gray(img, ".png", 8));
  const LoadedImage r = load_image(dir / "a.png");
  EXPECT_EQ(r.bit_depth, 8);
  EXPECT_FALSE(r.was_colour);
  EXPECT_EQ(r.image.full_scale, 255.0);
  EXPECT_EQ(r.image.pixels, img.pixels);
}

TEST(LoadImage, Reads16BitTiffWithoutLosingDepth) {
  const auto dir = test::scratch_dir("image_tif16");
  const Image img = ramp(33, 21, 65535);
  write_bytes(dir / "a.tif", encode_gray(img, ".tif", 16));
  const LoadedImage r = load_image(dir / "a.tif");
  EXPECT_EQ(r.bit_depth, 16);
  EXPECT_EQ(r.image.full_scale, 65535.0);
  EXPECT_EQ(r.image.pixels, img.pixels);
}

TEST(LoadImage, Reads8BitBmpAndTiffExactly) {
  const auto dir = test::scratch_dir("image_bmp_tif8");
  const Image img = ramp(37, 19, 255);
  for (const char* ext : {".bmp", ".tif"}) {
    const auto path = dir / (std::string("a") + ext);
    write_bytes(path, encode_gray(img, ext, 8));
    const LoadedImage r = load_image(path);
    EXPECT_EQ(r.bit_depth, 8) << ext;
    EXPECT_EQ(r.image.pixels, img.pixels) << ext;
  }
}

TEST(LoadImage, ConvertsColourToGrayWithAWarning) {
  const auto dir = test::scratch_dir("image_colour");
  RgbImage rgb(8, 6);
  for (std::size_t i = 0; i < rgb.rgb.size(); i += 3) rgb.rgb[i] = 200;  // pure red
  write_bytes(dir / "c.png", encode_png(rgb));
  const LoadedImage r = load_image(dir / "c.png");
  EXPECT_TRUE(r.was_colour);
  EXPECT_NE(r.warning.find("c.png"), std::string::npos);
  EXPECT_NEAR(r.image.at(3, 3), 0.299 * 200, 1.0);  // BT.601 luma of red
}

TEST(LoadImage, MissingFileIsAFileErrorNamingIt) {
  EXPECT_EQ(message_of("/nonexistent/frame_007.tif"), "/nonexistent/frame_007.tif: image not found");
}

TEST(LoadImage, UndecodableFileIsAFileErrorNamingIt) {
  const auto dir = test::scratch_dir("image_garbage");
  write_bytes(dir / "bad.png", "this is not a png");
  EXPECT_NE(message_of(dir / "bad.png").find("bad.png: cannot decode image"), std::string::npos);
}

// The image fuzzer's crash (issue 14): PNG bytes behind a 9-byte prefix with "DICM" at offset 128
// made OpenCV hand the file to GDCM, which aborts on it. Files of other formats than the cameras'
// never reach a decoder now.
TEST(LoadImage, AFileOfAnotherFormatNeverReachesADecoder) {
  const auto dir = test::scratch_dir("image_other_format");
  std::string dicom(136, '\0');
  dicom.replace(128, 4, "DICM");
  dicom.replace(9, 8, "\x89PNG\r\n\x1a\n");
  write_bytes(dir / "frame.png", dicom);
  const std::string m = message_of(dir / "frame.png");
  EXPECT_NE(m.find("frame.png: cannot decode image"), std::string::npos) << m;
  EXPECT_NE(m.find("not a TIFF, PNG, BMP, JPEG or PNM file (first bytes 0 0 0 0 0 0 0 0)"), std::string::npos) << m;
}

TEST(LoadImage, FrameOfAnotherSizeIsAFileErrorNamingItAndBothSizes) {
  try {
    require_same_size(Image(40, 30), Image(41, 30), "frame_2.png");
    FAIL() << "no error";
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()),
              "frame_2.png: image size differs from the reference image (got 41x30, expected 40x30)");
  }
}

TEST(GaussianBlur, KeepsAConstantImageAndSmoothsAnImpulseToUnitSum) {
  Image c(20, 20, 3.0f);
  EXPECT_NEAR(gaussian_blur(c, 1.0).at(0, 0), 3.0, 1e-5);
  Image d(21, 21);
  d.at(10, 10) = 1;
  const Image b = gaussian_blur(d, 1.0);
  double sum = 0;
  for (float v : b.pixels) sum += v;
  EXPECT_NEAR(sum, 1.0, 1e-5);
  EXPECT_NEAR(b.at(10, 10), 1 / (2 * std::numbers::pi), 2e-3);  // peak of a unit 2-D Gaussian, σ = 1
}
