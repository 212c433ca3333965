// `tricot synth` images (see synth_images.hpp).
#include "tricot/project/synth_images.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <future>

#include <nlohmann/json.hpp>

#include "output/json.hpp"
#include "spec/schema.hpp"

#include "tricot/core/error.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string frame_name(int j) { return fmt::format("frame_{:04d}.png", j); }

}  // namespace

io::SectionSpec synth_images_section() {
  io::SectionSpec s{"images",
                    "Camera images of the deformed full specimen (the paper's set-up: the camera on its pantograph\n"
                    "aims at the specimen centre, which stays at the image centre; the fabric's roughness is the\n"
                    "speckle). A built-in test's quarter is mirrored into the full specimen; a test of named\n"
                    "boundaries (kind = \"custom\") is its whole mesh, the mesh's origin at the image centre.\n"
                    "DIR/<test>/images/frame_0000.png is the unloaded reference, frame_NNNN.png shows\n"
                    "step NNNN · every_n_steps; camera.json gives the pixel size, centre pixel and axes (X right,\n"
                    "Y up, the keys of `tricot dic`'s [physical]) and each frame's step; frames.csv the test\n"
                    "machine's log per frame (frame, step, load, edge_displacement, edge_force: the force gauge).\n"
                    "The speckle pattern and the noise are seeded from [synth] seed.",
                    false,
                    {},
                    {}};
  add_keys(s, SynthImagesSpec{});
  return s;
}

SynthImagesSpec SynthImagesSpec::from_config(const io::Node& s) { return read_table<SynthImagesSpec>(s); }

void SynthImagesSpec::validate() const {
  try {
    check_ranges(*this);  // a spec built in code (a file's keys were checked when read)
  } catch (const InputError& e) {
    origin.rethrow(e);
  }
  if (!synth::texture_from_string(texture)) origin.fail("texture", "not a texture", texture, "\"speckle\" or \"knit\"");
  if (bits != 8 && bits != 16) origin.fail("bits", "PNG files are 8 or 16 bit", std::to_string(bits), "8 or 16");
}

synth::SpecimenImageOptions SynthImagesSpec::options(std::uint64_t seed) const {
  synth::SpecimenImageOptions o;
  o.camera.mm_per_px = pixel_size;
  o.camera.width = width;
  o.camera.height = height;
  o.speckle.texture = synth::texture_from_string(texture).value_or(synth::Texture::speckle);
  o.speckle.radius = 0.5 * speckle_size;
  o.speckle.coverage = coverage;
  o.speckle.subsamples = subsamples;
  o.speckle.seed = seed;
  o.background = background;
  o.noise = noise;
  o.bits = bits;
  return o;  // in the engine's ranges: validate() checked the keys (the renderer checks them again)
}

int write_images(const SynthImagesSpec& s, const fem::TestModel& model, const fem::SimulationResult& sim,
                 std::uint64_t seed, const fs::path& test_dir, const Log& log, const std::vector<double>& gauge_force) {
  synth::SpecimenImageOptions o = s.options(seed);
  o.speckle.wale_angle_deg = -model.material_angle;  // the wales along the material's axis 1; pixel y is down
  // A test of named conditions is a model of the whole specimen (any mesh); a built-in one, of its quarter.
  const synth::Extent extent = model.has_conditions() ? synth::Extent::whole : synth::Extent::quarter;
  const synth::SpecimenRenderer renderer(model.mesh, o, extent);
  // The timeline: frame 0 unloaded; a rig's setting increments and the held setting; the pull.
  struct Shot {
    const char* phase;
    int step, setting;
    const fem::StepResult* state;  // nullptr = unloaded
  };
  std::vector<Shot> shots{{"reference", 0, 0, nullptr}};
  if (s.setting_frames && !sim.setting.empty()) {
    const int n = static_cast<int>(sim.setting.size());
    for (int i = 1; i <= n; ++i) shots.push_back({"setting", 0, i, &sim.setting[std::size_t(i - 1)]});
    for (int h = 0; h < s.hold_frames; ++h) shots.push_back({"hold", 0, n, &sim.setting.back()});
  }
  const int steps = static_cast<int>(sim.steps.size());
  for (int step = s.every_n_steps; step <= steps; step += s.every_n_steps)
    shots.push_back({"pull", step, static_cast<int>(sim.setting.size()), &sim.steps[std::size_t(step - 1)]});
  const int frames = static_cast<int>(shots.size());
  const fs::path dir = test_dir / kImagesFolder;

  json list = json::array();
  io::Table gauge;  // frames.csv: what the test machine logs per frame
  gauge.columns = {"frame", "step", "load", "edge_displacement", "edge_force"};
  const Reporter reporter = log.reporter();
  // Frame j's PNG is encoded and written while frame j + 1 renders (the encoding is serial: about a
  // sixth of a frame's CPU at 1 MP, bench/synth_benchmark's BM_EncodePng).
  std::future<void> writing;
  for (int j = 0; j < frames; ++j) {
    const Shot& shot = shots[std::size_t(j)];
    const fem::StepResult* k = shot.state;
    image::Image img = renderer.render(k ? k->u : Eigen::VectorXd(), seed * 1000003 + std::uint64_t(j));
    if (writing.valid()) writing.get();  // rethrows a failed write
    writing = std::async(std::launch::async, [&dir, &o, j, frame = std::move(img)] {
      io::write_atomic(dir / frame_name(j), image::encode_gray(frame, ".png", o.bits));
    });
    list.push_back(json{{"frame", j},
                        {"file", frame_name(j)},
                        {"phase", shot.phase},
                        {"step", shot.step},
                        {"setting", shot.setting},
                        {"load", shot.step > 0 ? k->load : 0.0},
                        {"edge_displacement", k ? k->edge_displacement : 0.0},
                        {"edge_force", k ? k->edge_force : 0.0}});
    const bool read = shot.step > 0 && std::size_t(shot.step) <= gauge_force.size();
    gauge.rows.push_back({double(j), double(shot.step), shot.step > 0 ? k->load : 0.0, k ? k->edge_displacement : 0.0,
                          read ? gauge_force[std::size_t(shot.step - 1)]
                          : k  ? k->edge_force
                               : 0.0});
    reporter.report({"images " + model.name, std::size_t(j + 1), std::size_t(frames), frame_name(j)});
  }
  if (writing.valid()) writing.get();
  io::remove_numbered_files(dir, "frame_", ".png", frames);  // an earlier, longer run's

  const synth::Camera& c = o.camera;
  const json camera{
      {"mm_per_px", c.mm_per_px},
      {"centre_px", {c.centre_px()(0), c.centre_px()(1)}},
      {"angle_deg", 0.0},
      {"y_up", true},
      {"axes", extent == synth::Extent::quarter
                   ? "X = mm_per_px * (x - centre_px[0]) to the right, Y = -mm_per_px * (y - centre_px[1]) up, mm, "
                     "from the full specimen's centre; the FE quarter is X >= 0, Y >= 0"
                   : "X = mm_per_px * (x - centre_px[0]) to the right, Y = -mm_per_px * (y - centre_px[1]) up, mm: "
                     "the mesh's own frame, its origin at centre_px"},
      {"width", c.width},
      {"height", c.height},
      {"bits", o.bits},
      {"texture", synth::to_string(o.speckle.texture)},
      {"speckle_size_px", 2 * o.speckle.radius},
      {"noise", o.noise},
      {"seed", seed},
      {"frames", list},
  };
  io::write_atomic(dir / kCameraFile, camera.dump(2) + "\n");
  io::write_atomic(dir / "frames.csv", io::to_csv(gauge));
  return frames;
}

int CameraFile::setting_frames() const {
  return static_cast<int>(
      std::count_if(frames.begin(), frames.end(), [](const Frame& f) { return f.phase == "setting"; }));
}
int CameraFile::hold_frames() const {
  return static_cast<int>(
      std::count_if(frames.begin(), frames.end(), [](const Frame& f) { return f.phase == "hold"; }));
}

CameraFile read_camera(const fs::path& images_dir) {
  const fs::path path = images_dir / kCameraFile;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw FileError({path.string(), 0, ""}, "camera file not found");
  CameraFile out;
  std::string at;
  try {
    const json j = json::parse(io::read_text(path));
    at = "mm_per_px", out.camera.mm_per_px = j.at(at).get<double>();
    at = "width", out.camera.width = j.at(at).get<int>();
    at = "height", out.camera.height = j.at(at).get<int>();
    at = "frames";
    for (const json& f : j.at(at))
      out.frames.push_back({f.at("file").get<std::string>(),
                            f.value("phase", std::string(f.at("step").get<int>() > 0 ? "pull" : "reference")),
                            f.at("step").get<int>(), f.value("setting", 0), f.at("load").get<double>(),
                            f.at("edge_displacement").get<double>()});
  } catch (const json::exception& e) {
    throw InputError({path.string(), 0, at}, "malformed camera file: " + json_problem(e));
  }
  try {
    out.camera.validate();
  } catch (const InputError& e) {
    throw InputError({path.string(), 0, e.where().key}, e.problem());
  }
  return out;
}

}  // namespace tricot::project
