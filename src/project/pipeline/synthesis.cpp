// tricot synth's pipeline: FE-generated "measurements" with a known law (paper §3.3): the grip's
// displacement and force per step and the displacement at a grid of points, with optional Gaussian
// noise of a fixed seed, written as an experiment that `tricot identify` reads. Generate on a finer
// mesh than the identification's, so that the check is not an inverse crime.
#include "tricot/project/synthesis.hpp"

#include "tricot/project/output_dir.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "tricot/fem/locate.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/synthetic.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/synth_images.hpp"
#include "tricot/project/synth_lab.hpp"

#include "spec/schema.hpp"

namespace tricot::project {

namespace {

namespace fs = std::filesystem;

// [synth]: how the measurements are taken from the FE runs, each key declared once (core/options.hpp).
struct SynthSpec {
  double noise_edge_displacement = 0;
  double noise_edge_force = 0;
  double noise_field = 0;
  double noise_relative = 0;
  std::int64_t seed = 20070101;
  bool field = true;
  ident::FieldKind field_kind = ident::FieldKind::cumulative;
  int nx = 6;
  int ny = 20;
  double spacing = 0;
  double inset = 1;

  static auto keys() {
    using O = SynthSpec;
    return std::tuple{
        option(&O::noise_edge_displacement, "synth.noise_edge_displacement",
               "σ of the grip displacement, mm (absolute), ≥ 0.", 0, 1e6),
        option(&O::noise_edge_force, "synth.noise_edge_force", "σ of the grip force, N (absolute), ≥ 0.", 0, 1e9),
        option(&O::noise_field, "synth.noise_field", "σ of u and v at the field points, mm (absolute), ≥ 0.", 0, 1e6),
        option(&O::noise_relative, "synth.noise_relative",
               "σ as a fraction of each group's RMS (edge displacement, edge force, field u and v together),\n"
               "per test: 0.005 = 0.5 %. Replaces the absolute σ; give one or the other.",
               0, 1),
        option(&O::seed, "synth.seed", "Seed of the noise generator (std::mt19937_64).", 0, 9.2e18),
        option(&O::field, "synth.field", "Write field.csv (displacements at points); false = edge data only."),
        option(&O::field_kind, "synth.field_kind",
               "cumulative: u(X, t_k) of material points tracked from the reference (x, y = X).\n"
               "incremental: x(t_k) − x(t_{k−1}) of the material under points fixed in the images (the\n"
               "paper's window centres); points that leave the specimen are left out (the summary says how many).",
               {{ident::FieldKind::cumulative, "cumulative"}, {ident::FieldKind::incremental, "incremental"}}),
        option(&O::nx, "synth.nx", "Field points across the quarter's width (a regular grid).", 1, 10000),
        option(&O::ny, "synth.ny", "Field points along the quarter's height.", 1, 10000),
        option(&O::spacing, "synth.spacing",
               "DIC-like grid: a point every `spacing` mm from the inset corner (like the centres of DIC\n"
               "subsets); 0 = the nx × ny grid.",
               0, 1e5),
        option(&O::inset, "synth.inset", "Distance of the outermost points from the quarter's edges, mm, ≥ 0.", 0,
               1e5)};
  }
};

io::SectionSpec synth_section() {
  io::SectionSpec s{"synth",
                    "How the synthetic measurements are taken from the FE runs: noise and field points.\n"
                    "Noise is Gaussian, independent per value, from a generator seeded with seed + the test's\n"
                    "index (ident::add_noise), so a run is reproducible.",
                    false,
                    {},
                    {}};
  add_keys(s, SynthSpec{});
  s.sections.push_back(synth_images_section());  // [synth.images]
  s.sections.push_back(synth_lab_section());     // [synth.lab]
  return s;
}

// Positions of the field points in the box [lo, lo + (W, H)] (the quarter, or the bounding box of any
// mesh: points in its holes are left out later): the nx × ny grid, or every `spacing` mm.
Eigen::Matrix2Xd grid_points(const io::Node& node, const SynthSpec& s, const Vec2& lo, double W, double H,
                             const io::Node& test) {
  const double inset = s.inset;
  if (2 * inset >= std::min(W, H))
    node.fail("inset", fmt::format("leaves no room for points in test '{}' ({} × {} mm)", test.string("name"), W, H),
              io::to_toml(inset), fmt::format("< {} mm", std::min(W, H) / 2));
  auto axis = [&](double length, std::int64_t n) {
    std::vector<double> a;
    const double spacing = s.spacing;
    if (spacing > 0) {
      for (double x = inset; x <= length - inset + 1e-9 * length; x += spacing) a.push_back(x);
    } else if (n == 1) {
      a.push_back(length / 2);
    } else {
      for (std::int64_t i = 0; i < n; ++i) a.push_back(inset + (length - 2 * inset) * double(i) / double(n - 1));
    }
    return a;
  };
  const auto xs = axis(W, s.nx), ys = axis(H, s.ny);
  Eigen::Matrix2Xd P(2, xs.size() * ys.size());
  Eigen::Index c = 0;
  for (double y : ys)
    for (double x : xs) P.col(c++) = lo + Vec2(x, y);
  return P;
}

// Incremental data are taken at points fixed in the images: a point that leaves the specimen at some
// step (the strip narrows under it) has no data, as in DIC; the others are kept, with their grid ids.
std::vector<int> inside_at_every_step(const fem::TestModel& model, const fem::SimulationResult& sim,
                                      const Eigen::Matrix2Xd& grid, ident::FieldKind kind) {
  std::vector<char> keep(grid.cols(), 1);
  for (std::size_t k = 0; k < sim.steps.size(); ++k) {
    if (kind == ident::FieldKind::cumulative && k > 0) break;
    const bool moved = kind == ident::FieldKind::incremental && k > 0;
    const fem::PointLocator locator(model.mesh, moved ? &sim.steps[k - 1].u : nullptr);
    for (Eigen::Index p = 0; p < grid.cols(); ++p)
      if (keep[p] && !locator.locate(grid.col(p))) keep[p] = 0;
  }
  std::vector<int> kept;
  for (Eigen::Index p = 0; p < grid.cols(); ++p)
    if (keep[p]) kept.push_back(static_cast<int>(p));
  return kept;
}

// A test that does not converge with the true law: the run's data would be incomplete (exit 4).
class NotConverged : public InputError {
 public:
  using InputError::InputError;
  ExitCode exit_code() const override { return ExitCode::not_converged; }
};

}  // namespace

io::SectionSpec synth_schema() {
  io::SectionSpec root = case_schema();
  root.help =
      "tricot synth: an experiment file. The case (specimen, law with the TRUE coefficients, solver,\n"
      "tests) is run once and its grip and field values are written as measurements, with noise.\n"
      "Units: mm, N, N/mm, degrees.";
  root.sections.push_back(synth_section());
  return root;
}

Truth synthesize(const io::Node& root, const fs::path& dir, const Log& log) {
  const CaseSpec spec = CaseSpec::from_config(root);
  spec.check_tests();
  const auto law = spec.law.law(spec.mesh.region_names());
  const fem::SolveOptions solver = spec.solver.options();
  const io::Node& node = root.section("synth");
  SynthSpec s;
  read_keys(node, s);
  if (s.noise_relative > 0)
    for (const auto& [k, sigma] :
         {std::pair{"noise_edge_displacement", s.noise_edge_displacement},
          std::pair{"noise_edge_force", s.noise_edge_force}, std::pair{"noise_field", s.noise_field}})
      if (sigma > 0)
        node.fail(k, "give either absolute σ or noise_relative, not both", io::to_toml(sigma), "0 with noise_relative");
  const ident::FieldKind kind = s.field_kind;
  const SynthImagesSpec images = SynthImagesSpec::from_config(node.section("images"));
  const SynthLabSpec lab = SynthLabSpec::from_config(node.section("lab"));
  const bool with_images = images.enabled;
  if (with_images) images.validate();  // a bad [synth.images] stops before any work

  // Build every test first: a config error stops before any work.
  std::vector<fem::TestModel> models;
  for (const auto& t : spec.test) {
    if (t.test_kind() == TestKind::simple_shear)
      t.origin.fail("kind", "synth needs an FE test", "\"simple_shear\"",
                    "uniaxial, biaxial, homogeneous, rig or custom");
    models.push_back(t.model(spec.mesh, spec.rig));
  }

  OutputDir output(dir, "synth");  // written in staging, published at the end (issue 14)
  const fs::path staged = output.staging();
  Truth truth;
  truth.law = law->name();
  truth.names = law->coefficient_names();
  const Eigen::VectorXd c = law->coefficients();
  truth.values.assign(c.data(), c.data() + c.size());
  truth.noise_relative = s.noise_relative;
  truth.seed = static_cast<std::uint64_t>(s.seed);
  truth.field_kind = kind;

  std::vector<ident::TestData> data;
  const auto& nodes = root.array("test");
  for (std::size_t i = 0; i < models.size(); ++i) {
    const fem::TestModel& model = models[i];
    const fem::SimulationResult sim = fem::simulate(model, *law, solver, log.reporter());
    if (!sim.usable())
      throw NotConverged(
          nodes[i].where("name"),
          fmt::format("test '{}' did not converge with the true law, so it has no data: {}", model.name, sim.message));
    Eigen::Matrix2Xd points(2, 0);
    std::vector<int> ids;
    int dropped = 0;
    if (s.field) {
      Vec2 lo = Vec2::Zero(), size;
      if (model.has_conditions()) {  // any mesh: its bounding box
        lo = model.mesh.X.rowwise().minCoeff();
        size = model.mesh.X.rowwise().maxCoeff() - lo;
      } else {
        const fem::MeshOptions quarter = spec.test[i].mesh_options(spec.mesh);
        size = Vec2(quarter.width, quarter.height);
      }
      const Eigen::Matrix2Xd grid = grid_points(node, s, lo, size.x(), size.y(), nodes[i]);
      const std::vector<int> kept = inside_at_every_step(model, sim, grid, kind);
      dropped = static_cast<int>(grid.cols()) - static_cast<int>(kept.size());
      points.resize(2, Eigen::Index(kept.size()));
      for (std::size_t q = 0; q < kept.size(); ++q) {
        points.col(Eigen::Index(q)) = grid.col(kept[q]);
        ids.push_back(kept[q] + 1);  // ids number the grid: a point left out leaves a gap
      }
    }
    ident::TestData d = ident::measure(model, sim, points, ids, kind);
    const ident::Sigma sigma = s.noise_relative > 0
                                   ? ident::rms_fraction(d, s.noise_relative)
                                   : ident::Sigma{s.noise_edge_displacement, s.noise_edge_force, s.noise_field};
    ident::add_noise(d, sigma, truth.seed + i);  // one stream per test
    data.push_back(d);

    Truth::Test tt;
    tt.name = model.name;
    tt.control = model.control == fem::GripControl::force ? "force" : "displacement";
    tt.mesh = spec.test[i].mesh_options(spec.mesh);
    tt.dofs = model.mesh.dofs();
    tt.steps = d.steps();
    tt.points = d.point_count();
    tt.dropped_points = dropped;
    tt.sigma = sigma;
    truth.tests.push_back(tt);

    const auto& last = sim.steps.back();
    std::string noise = "noise-free";
    if (sigma.edge_displacement > 0 || sigma.edge_force > 0 || sigma.field > 0)
      noise = fmt::format("σ = {:.3g} mm (grip), {:.3g} N (force), {:.3g} mm (field)", sigma.edge_displacement,
                          sigma.edge_force, sigma.field);
    std::string field = d.has_field() ? fmt::format("{} {} field points", d.point_count(), ident::to_string(kind))
                                      : std::string("no field");
    if (dropped > 0) field += fmt::format(" ({} left the specimen and were left out)", dropped);
    if (with_images) {  // the speckle of test i is seeded with seed + i, like its noise
      const int frames = write_images(images, model, sim, truth.seed + i, staged / model.name, log, d.edge_force);
      field += fmt::format("; {} images in {}", frames, (dir / model.name / kImagesFolder / "").string());
      if (lab.enabled) write_lab_record(lab, sim, staged / model.name, truth.seed + i, log);
    }
    log.print(fmt::format("{}: {} steps on {} {} dofs in {}; last step {:.5g} N at {:.5g} mm; {}; {}", model.name,
                          d.steps(), tt.dofs, fem::to_string(tt.mesh.type), format_duration(sim.seconds),
                          last.edge_force, last.edge_displacement, field, noise));
  }
  for (const auto& d : data) write_test_data(staged, d);
  write_truth(staged, truth);
  output.publish();
  std::string coefficients;
  for (std::size_t k = 0; k < truth.names.size(); ++k)
    coefficients += fmt::format("{}{} = {:.6g}", k ? ", " : "", truth.names[k], truth.values[k]);
  log.print(fmt::format("truth ({}): {}; seed {} -> {}", truth.law, coefficients, truth.seed, (dir / "").string()));
  return truth;
}

}  // namespace tricot::project
