// The image loader (image::load_image: OpenCV's decoders, then tricot's depth and colour handling) on
// arbitrary bytes named .png, .tif or .bmp (the first byte picks).
#include "fuzz.hpp"
#include "tricot/image/image.hpp"

using namespace tricot;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* kExtensions[] = {".png", ".tif", ".bmp"};
  const auto file =
      fuzz::write(fuzz::scratch(std::string("fuzz") + kExtensions[data[0] % 3]), fuzz::view(data + 1, size - 1));
  try {
    const image::LoadedImage img = image::load_image(file);
    image::require_same_size(img.image, img.image, file);
  } catch (const InputError&) {}
  return 0;
}
