// checkpoint.json (src/project/output/checkpoint.cpp): LM's state and phase round-trip exactly; a bad phase is
// named; a checkpoint written before the phase existed resumes LM.
#include "tricot/project/checkpoint.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include "testing/paths.hpp"
#include "tricot/core/error.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;

ident::Checkpoint sample() {
  ident::Checkpoint c;
  c.names = {"C10", "C03"};
  c.scales = Eigen::Vector2d(0.05, 0.01);
  c.x = Eigen::Vector2d(1.0 / 3.0, -2.0 / 7.0);  // not representable in few digits: the round trip is exact
  c.parameters = c.scales.cwiseProduct(c.x);
  c.objective = 1.2345678901234567e-9;
  c.trust_region_radius = 2310.4520291373137;
  c.iterations = 7;
  c.evaluations = 19;
  c.restarts = 1;
  c.history.push_back({0, 0.5, Eigen::Vector2d(0.05, 0.01), 0});
  c.phase = ident::Phase::stability;
  c.termination = ident::Termination::step_below_delta;
  c.message = "relative step max|t| = 3e-06 < delta = 1e-05 (eq. 3)";
  c.stability_passed = false;
  c.held = {1};
  return c;
}

fs::path file(const std::string& name) {
  return test::scratch_dir("checkpoint_" + name + "_" + std::to_string(::getpid())) / kCheckpointFile;
}

TEST(Checkpoint, LmStateAndPhaseRoundTripExactly) {
  const fs::path f = file("round_trip");
  const ident::Checkpoint c = sample();
  write_checkpoint(f, c, "fp");
  const ident::Checkpoint r = read_checkpoint(f, "fp");
  EXPECT_EQ(r.x, c.x);  // bit for bit: the resumed LM starts where the killed one was
  EXPECT_EQ(r.trust_region_radius, c.trust_region_radius);
  EXPECT_EQ(r.objective, c.objective);
  EXPECT_EQ(r.iterations, 7);
  EXPECT_EQ(r.restarts, 1);
  EXPECT_EQ(r.phase, ident::Phase::stability);
  EXPECT_EQ(r.termination, ident::Termination::step_below_delta);
  EXPECT_EQ(r.message, c.message);
  EXPECT_FALSE(r.stability_passed);
  EXPECT_EQ(r.held, c.held);  // the active set: LM goes on in the same free variables
  ASSERT_EQ(r.history.size(), 1u);
}

TEST(Checkpoint, AnUnknownPhaseIsNamed) {
  const fs::path f = file("bad_phase");
  write_checkpoint(f, sample(), "fp");
  std::string text = io::read_text(f);
  text.replace(text.find("\"stability\""), 11, "\"later\"");
  io::write_atomic(f, text);
  try {
    read_checkpoint(f, "fp");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "phase");
    EXPECT_EQ(e.where().file, f.string());
  }
}

// A value of the wrong type names the key and shows the value (it was nlohmann's raw type_error).
TEST(Checkpoint, AValueOfTheWrongTypeNamesItsKey) {
  const fs::path f = file("wrong_type");
  write_checkpoint(f, sample(), "fp");
  std::string text = io::read_text(f);
  const auto at = text.find("\"iterations\": ") + 14;
  text.replace(at, text.find(',', at) - at, "\"seven\"");
  io::write_atomic(f, text);
  try {
    read_checkpoint(f, "fp");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, "iterations");
    EXPECT_NE(std::string(e.what()).find("\"seven\""), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
  }
}

TEST(Checkpoint, OneWrittenBeforeThePhaseExistedResumesLm) {
  const fs::path f = file("old");
  write_checkpoint(f, sample(), "fp");
  std::string text = io::read_text(f);
  for (const char* key : {"\"phase\"", "\"termination\"", "\"stability_passed\""}) {
    const auto at = text.find(key);
    text.erase(at, text.find('\n', at) - at + 1);
  }
  io::write_atomic(f, text);
  const ident::Checkpoint r = read_checkpoint(f, "fp");
  EXPECT_EQ(r.phase, ident::Phase::lm);
  EXPECT_EQ(r.x, sample().x);
}

}  // namespace
}  // namespace tricot::project
