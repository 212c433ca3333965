// `tricot synth` images: camera pictures of the deformed specimen (synth::SpecimenRenderer), written
// beside the test's data when the experiment file has `[synth.images] enabled = true`:
//
//   DIR/<test>/images/frame_0000.png   the unloaded reference
//   DIR/<test>/images/frame_NNNN.png   frame j shows step j · every_n_steps (steps 1..K as forces.csv)
//   DIR/<test>/images/camera.json      pixel size, centre pixel and axes (the keys of `tricot dic`'s
//                                      [physical] table) and, per frame, its file, step and load
//
// Specimen coordinates: X = mm_per_px · (x − centre_px[0]) to the right, Y = −mm_per_px · (y −
// centre_px[1]) up, origin at the full specimen's centre; the FE quarter is X, Y ≥ 0.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tricot/project/log.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"
#include "tricot/synth/specimen.hpp"

namespace tricot::project {

inline constexpr const char* kImagesFolder = "images";
inline constexpr const char* kCameraFile = "camera.json";

/// `[synth.images]`: enabled, pixel_size, width, height, speckle_size, coverage, subsamples,
/// background, noise, bits, every_n_steps.
io::SectionSpec synth_images_section();

/// The renderer's options from a validated `[synth.images]` table; `seed` fixes the speckle.
/// Throws InputError located at the key for what the schema cannot check (bits 8 or 16).
synth::SpecimenImageOptions build_image_options(const io::Node& images, std::uint64_t seed);

/// Renders frame 0 (unloaded) and every `every_n_steps`-th step of `sim` and writes them, and
/// camera.json, atomically to `test_dir`/images (older frames beyond the new count are removed).
/// Noise of frame j is drawn from `seed` and j. Returns the number of frames written.
int write_images(const io::Node& images, const fem::TestModel& model, const fem::SimulationResult& sim,
                 std::uint64_t seed, const std::filesystem::path& test_dir, const Log& log);

/// What camera.json holds.
struct CameraFile {
  synth::Camera camera;
  struct Frame {
    std::string file;
    int step = 0;  ///< 0 = unloaded
    double load = 0, edge_displacement = 0;
  };
  std::vector<Frame> frames;
};
/// Reads DIR/camera.json (DIR = the images folder). FileError when missing, InputError when malformed.
CameraFile read_camera(const std::filesystem::path& images_dir);

}  // namespace tricot::project
