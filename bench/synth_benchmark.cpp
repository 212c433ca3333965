// The synthetic camera (issue 32): CPU per 1 MP frame of SpecimenRenderer::render on the demo's set-up
// (`tricot demo`'s [synth.images]: 1280 × 1024 px at 0.2 mm/px, knit texture of 5 px stitches, 2 × 2
// sub-samples, 8 bit, noise 1 gray level; the quarter 55 × 55 mm on 24 × 20 graded Q8 stretched 1.6×
// along the pull and necked), on one thread, against:
//   - OldRenderer: the renderer before issue 32, kept here as the reference: per sub-sample, the
//     material point by FullSpecimen::material_point (Newton from the previous sub-sample's element,
//     the locator where that fails) and the pattern's exact intensity (every neighbouring blob);
//   - PatternTable: the texture's table, made once per test (per renderer), not per frame;
//   - the physical limits of one 1 MP float image: filling it and copying it (memory bandwidth), and
//     the parts of a frame that are not the picture: the noise, and encoding the PNG.
// Counters: `Mpx_per_s` megapixels per CPU second; `rms_vs_old` the RMS difference (gray levels of 255)
// between the new and the old image, both without noise (OldRenderer only).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstring>

#include "tricot/fem/mesh.hpp"
#include "tricot/image/image.hpp"
#include "tricot/synth/specimen.hpp"

using namespace tricot;
using namespace tricot::synth;

namespace {

struct Scene {
  fem::Mesh mesh;
  Eigen::VectorXd u;
  SpecimenImageOptions options;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene s;
    fem::MeshOptions m;
    m.width = 55, m.height = 55, m.nx = 24, m.ny = 20, m.grading = 0.5, m.grading_x = 0.5;
    s.mesh = fem::make_quarter_mesh(m);
    s.u.resize(s.mesh.dofs());
    for (int n = 0; n < s.mesh.nodes(); ++n) {
      const double X = s.mesh.X(0, n), Y = s.mesh.X(1, n), eta = Y / 55;
      s.u.segment<2>(2 * n) = Vec2(-0.2 * X * (1 - eta * eta), 0.6 * Y + 0.002 * X * X * eta);
    }
    SpecimenImageOptions& o = s.options;
    o.camera = {0.2, 1280, 1024};
    o.speckle.texture = Texture::knit;
    o.speckle.radius = 2.5;
    o.speckle.subsamples = 2;
    o.speckle.seed = 20070412;
    o.speckle.wale_angle_deg = -90;
    o.noise = 1;
    o.bits = 8;
    o.threads = 1;
    return s;
  }();
  return s;
}

constexpr double kMegapixels = 1280 * 1024 / 1e6;

// Arg 1: the demo's frame (noise, 8 bit); arg 0: the picture alone (float, no noise).
void BM_RenderFrame(benchmark::State& state) {
  const Scene& s = scene();
  SpecimenImageOptions o = s.options;
  if (state.range(0) == 0) o.bits = 32, o.noise = 0;
  const SpecimenRenderer r(s.mesh, o);
  for (auto _ : state) benchmark::DoNotOptimize(r.render(s.u, 7));
  state.counters["Mpx_per_s"] =
      benchmark::Counter(kMegapixels * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

image::Image old_render(const SpecimenRenderer& r, const fem::Mesh& mesh, const Eigen::VectorXd& u) {
  const FullSpecimen body(mesh, u);
  const SpecimenImageOptions& o = r.options();
  const Camera& c = o.camera;
  const int s = o.speckle.subsamples;
  image::Image img(c.width, c.height, 0.0f, 1.0);
  std::array<fem::Location, 16> right, left;
  const int c0 = c.width / 2;
  const auto pixel = [&](int x, int y, std::array<fem::Location, 16>& hints) {
    double sum = 0;
    for (int b = 0; b < s; ++b)
      for (int a = 0; a < s; ++a) {
        const Vec2 xs(x - 0.5 + (a + 0.5) / s, y - 0.5 + (b + 0.5) / s);
        const auto X = body.material_point(c.to_specimen(xs), &hints[std::size_t(b)]);
        sum += X ? r.pattern().intensity(c.to_pixel(*X)) : o.background;
      }
    img.at(x, y) = static_cast<float>(sum / (s * s));
  };
  for (int y = 0; y < c.height; ++y) {
    right = {};
    pixel(c0, y, right);
    left = right;
    for (int x = c0 + 1; x < c.width; ++x) pixel(x, y, right);
    for (int x = c0 - 1; x >= 0; --x) pixel(x, y, left);
  }
  return img;
}

void BM_OldRenderer(benchmark::State& state) {
  const Scene& s = scene();
  SpecimenImageOptions o = s.options;
  o.bits = 32, o.noise = 0;
  const SpecimenRenderer r(s.mesh, o);
  image::Image old;
  for (auto _ : state) old = old_render(r, s.mesh, s.u);
  const image::Image now = r.render(s.u);
  double d2 = 0;
  for (std::size_t i = 0; i < now.pixels.size(); ++i) d2 += std::pow(255.0 * (now.pixels[i] - old.pixels[i]), 2);
  state.counters["Mpx_per_s"] =
      benchmark::Counter(kMegapixels * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["rms_vs_old"] = std::sqrt(d2 / double(now.pixels.size()));
}
BENCHMARK(BM_OldRenderer)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

void BM_PatternTable(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) benchmark::DoNotOptimize(SpecimenRenderer(s.mesh, s.options).table().step());
}
BENCHMARK(BM_PatternTable)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FillFrame(benchmark::State& state) {
  image::Image img(1280, 1024);
  float v = 0;
  for (auto _ : state) {
    std::fill(img.pixels.begin(), img.pixels.end(), v += 1);
    benchmark::ClobberMemory();
  }
  state.counters["Mpx_per_s"] =
      benchmark::Counter(kMegapixels * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(img.pixels.size() * sizeof(float)));
}
BENCHMARK(BM_FillFrame)->Unit(benchmark::kMicrosecond);

void BM_CopyFrame(benchmark::State& state) {
  const image::Image a(1280, 1024, 0.5f);
  image::Image b(1280, 1024);
  for (auto _ : state) {
    std::memcpy(b.pixels.data(), a.pixels.data(), a.pixels.size() * sizeof(float));
    benchmark::ClobberMemory();
  }
  state.counters["Mpx_per_s"] =
      benchmark::Counter(kMegapixels * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(2 * a.pixels.size() * sizeof(float)));
}
BENCHMARK(BM_CopyFrame)->Unit(benchmark::kMicrosecond);

void BM_AddNoise(benchmark::State& state) {
  const image::Image a(1280, 1024, 0.5f);
  for (auto _ : state) benchmark::DoNotOptimize(add_noise(a, 1 / 255.0, 7));
}
BENCHMARK(BM_AddNoise)->Unit(benchmark::kMillisecond);

void BM_EncodePng(benchmark::State& state) {
  const Scene& s = scene();
  const image::Image img = SpecimenRenderer(s.mesh, s.options).render(s.u, 7);
  for (auto _ : state) benchmark::DoNotOptimize(image::encode_gray(img, ".png", 8));
}
BENCHMARK(BM_EncodePng)->Unit(benchmark::kMillisecond);

}  // namespace
