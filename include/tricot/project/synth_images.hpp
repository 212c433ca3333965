// `tricot synth` images: camera pictures of the deformed specimen (synth::SpecimenRenderer), written
// beside the test's data when the experiment file has `[synth.images] enabled = true`:
//
//   DIR/<test>/images/frame_0000.png   the unloaded reference
//   DIR/<test>/images/frame_NNNN.png   frame j shows step j · every_n_steps (steps 1..K as forces.csv);
//                                      a rig test with setting_frames first shows its setting
//                                      increments, then hold_frames of the held setting, then the pull
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

#include "tricot/core/options.hpp"
#include "tricot/project/log.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/spec.hpp"
#include "tricot/synth/specimen.hpp"

namespace tricot::project {

inline constexpr const char* kImagesFolder = "images";
inline constexpr const char* kCameraFile = "camera.json";

/// `[synth.images]`, generated from SynthImagesSpec::keys() (defaults: SynthImagesSpec's).
io::SectionSpec synth_images_section();

/// `[synth.images]` as a typed spec: each key declared once in keys() (core/options.hpp).
struct SynthImagesSpec {
  bool enabled = false;
  double pixel_size = 0.1;          ///< mm/px on the specimen
  int width = 600;                  ///< px
  int height = 600;                 ///< px
  std::string texture = "speckle";  ///< "speckle" (painted) or "knit" (the knit's own stitches)
  double speckle_size = 5;          ///< px: twice the mean blob radius
  double coverage = 0.6;            ///< blobs per unit area × π r²
  int subsamples = 4;               ///< per pixel and direction
  double background = 0.5;          ///< gray beside the specimen, fraction of full scale
  double noise = 0;                 ///< σ of the camera noise, gray levels of the output
  int bits = 8;                     ///< 8 or 16
  int every_n_steps = 1;            ///< frame j shows step j · every_n_steps
  /// A rig test's setting (fem::SimulationResult::setting) in frames of its own, then `hold_frames`
  /// frames of the held setting, before the pull (the lab's set, hold, pull); false = the pull's
  /// frames only (frame 1 then holds the whole setting and the first pull increment).
  bool setting_frames = true;
  int hold_frames = 2;  ///< frames of the held setting before the pull, 0–1000
  Origin origin{"synth.images"};

  static auto keys() {
    using O = SynthImagesSpec;
    return std::tuple{
        option(&O::enabled, "synth.images.enabled",
               "Write the images (about 0.1 s of CPU per 1280 × 1024 px frame with 2 × 2 subsamples, the PNG "
               "included)."),
        option(&O::pixel_size, "synth.images.pixel_size", "Pixel size on the specimen, mm/px, > 0.", 1e-6, 1e4),
        option(&O::width, "synth.images.width", "Image width, px.", 8, 20000),
        option(&O::height, "synth.images.height", "Image height, px.", 8, 20000),
        OptionKey<O, std::string>{
            &O::texture,
            "synth.images.texture",
            "What the camera sees: \"speckle\" (a painted speckle of round blobs) or \"knit\" (the knit's\n"
            "natural tracers, as the paper: stitches in wales along the material's wale axis, each a V of two\n"
            "legs, pitch 2 speckle_size across the wales and 1.6 speckle_size along them, with yarn fuzz).",
            -1e300,
            1e300,
            {"speckle", "knit"}},
        option(&O::speckle_size, "synth.images.speckle_size",
               "Speckle size in px of the reference image (twice the mean blob radius).", 0.2, 2000),
        option(&O::coverage, "synth.images.coverage",
               "Speckle density: blobs per unit area × π r² (0.6: bright blobs cover about 45 % of the area).", 0.01,
               99),
        option(&O::subsamples, "synth.images.subsamples",
               "Samples per pixel and direction that integrate each pixel's area.", 1, 16),
        option(&O::background, "synth.images.background",
               "Flat gray beside the specimen and beyond the grips, fraction of full scale.", 0, 1),
        option(&O::noise, "synth.images.noise",
               "σ of Gaussian camera noise in gray levels of the output (8 bit: of 255), ≥ 0.", 0, 1e5),
        option(&O::bits, "synth.images.bits", "Bit depth of the PNG files: 8 or 16.", 8, 16),
        option(&O::every_n_steps, "synth.images.every_n_steps", "A frame every n steps (frame j shows step j · n).", 1,
               100000),
        option(&O::setting_frames, "synth.images.setting_frames",
               "A rig test: one frame per increment of its transverse setting (the grip at rest), then\n"
               "hold_frames of the held setting, then the pull's frames (the lab's set, hold, pull; camera.json\n"
               "gives each frame's phase). false: the pull's frames only (frame 1 holds the whole setting)."),
        option(&O::hold_frames, "synth.images.hold_frames",
               "Frames of the held setting before the pull (with setting_frames): the rest the synchronisation\n"
               "sees before the cross-head moves.",
               0, 1000)};
  }

  static SynthImagesSpec from_config(const io::Node& images);
  /// The one check: every key in its range (as a file's are), bits 8 or 16. Throws InputError naming
  /// the key, the value and the range.
  void validate() const;
  /// The renderer's options (validate() first); `seed` fixes the speckle.
  synth::SpecimenImageOptions options(std::uint64_t seed) const;
};

/// Renders frame 0 (unloaded) and every `every_n_steps`-th step of `sim` and writes them, camera.json
/// and frames.csv, atomically to `test_dir`/images (older frames beyond the new count are removed).
/// A test of named conditions is rendered as the whole specimen, a built-in one as its mirrored
/// quarter. Noise of frame j is drawn from `seed` and j. `gauge_force` (one per step, or empty for
/// the model's) is the force gauge's reading that frames.csv logs: the measured, noisy force. Returns
/// the number of frames written. `images` is validated (SynthImagesSpec::validate()).
int write_images(const SynthImagesSpec& images, const fem::TestModel& model, const fem::SimulationResult& sim,
                 std::uint64_t seed, const std::filesystem::path& test_dir, const Log& log,
                 const std::vector<double>& gauge_force = {});

/// What camera.json holds.
struct CameraFile {
  synth::Camera camera;
  struct Frame {
    std::string file;
    /// "reference" (frame 0, unloaded), "setting" (the rig's transverse setting, increment `setting`),
    /// "hold" (the setting held, the grip at rest) or "pull" (load step `step`)
    std::string phase = "pull";
    int step = 0;     ///< load step shown, 1-based (0 = none: the reference, setting and hold frames)
    int setting = 0;  ///< setting increment shown, 1-based (the hold frames: the last one)
    double load = 0, edge_displacement = 0;
  };
  std::vector<Frame> frames;
  /// Frames before the pull's first step, after frame 0: the setting and hold frames.
  int setting_frames() const;
  int hold_frames() const;
};
/// Reads DIR/camera.json (DIR = the images folder). FileError when missing, InputError when malformed.
CameraFile read_camera(const std::filesystem::path& images_dir);

}  // namespace tricot::project
