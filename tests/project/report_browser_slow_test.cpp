// The lab report in a real browser (issue 13): a small synth + identify, then headless Chromium opens
// DIR/report.html, checks that every figure decoded, screenshots the page and prints it to PDF.
// The screenshot stays at build/scratch/report_browser/report.png. Skips when Chromium is absent
// (scripts/install-deps installs Debian's `chromium`).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <regex>

#include "testing/cli.hpp"
#include "testing/experiment_case.hpp"
#include "testing/paths.hpp"
#include "tricot/io/files.hpp"

namespace tricot::project {
namespace {

namespace fs = std::filesystem;

struct Shell {
  int status = -1;
  std::string out;
};

// Runs `cmd` through the shell, stdout and stderr together.
Shell shell(const std::string& cmd) {
  Shell r;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), int(buf.size()), p)) r.out += buf.data();
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    if (shell(std::string("command -v ") + name).status == 0) return name;
  return {};
}

// Headless Chromium with its own profile folder (ctest may run two browsers at once) and a hard
// time limit: a browser that hangs fails the test, not the CI job.
std::string browser(const std::string& exe, const fs::path& dir) {
  return "timeout 180 " + exe +
         " --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run "
         "--hide-scrollbars --user-data-dir=" +
         (dir / "profile").string();
}

// Marks the page once loaded: how many <img> decoded (complete, naturalWidth > 0) of how many.
constexpr const char* kImageCheck = R"(<script>
window.addEventListener('load', function () {
  var imgs = Array.prototype.slice.call(document.images);
  var ok = imgs.filter(function (i) { return i.complete && i.naturalWidth > 0 && i.naturalHeight > 0; });
  var p = document.createElement('pre');
  p.id = 'image-check';
  p.textContent = 'images ' + ok.length + '/' + imgs.length;
  document.body.appendChild(p);
});
</script>
)";

// Opens `html` in the browser: every one of its `images` figures decoded, a screenshot kept beside it
// (`png`), and a valid A4 PDF print.
void check_in_browser(const std::string& exe, const fs::path& dir, const fs::path& html, std::size_t images,
                      const fs::path& png, int height) {
  const std::string page = io::read_text(html);
  std::string checked = page;
  checked.insert(checked.rfind("</body>"), kImageCheck);
  io::write_atomic(dir / "checked.html", checked);
  const Shell dom =
      shell(browser(exe, dir) + " --virtual-time-budget=10000 --dump-dom file://" + (dir / "checked.html").string());
  ASSERT_EQ(dom.status, 0) << dom.out;
  EXPECT_NE(dom.out.find("images " + std::to_string(images) + "/" + std::to_string(images)), std::string::npos)
      << dom.out.substr(dom.out.rfind("image-check") == std::string::npos ? 0 : dom.out.rfind("image-check"), 200);

  // The screenshot, kept under the build tree for a reader to look at.
  const Shell shot = shell(browser(exe, dir) + " --window-size=1100," + std::to_string(height) +
                           " --screenshot=" + png.string() + " file://" + html.string());
  ASSERT_EQ(shot.status, 0) << shot.out;
  const std::string shot_bytes = io::read_text(png);
  EXPECT_EQ(shot_bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  // The print: a valid PDF of at least one A4 page.
  const fs::path pdf = fs::path(png).replace_extension(".pdf");
  const Shell print =
      shell(browser(exe, dir) + " --no-pdf-header-footer --print-to-pdf=" + pdf.string() + " file://" + html.string());
  ASSERT_EQ(print.status, 0) << print.out;
  const std::string pdf_bytes = io::read_text(pdf);
  ASSERT_GE(pdf_bytes.size(), 1000u);
  EXPECT_EQ(pdf_bytes.substr(0, 5), "%PDF-");
  EXPECT_NE(pdf_bytes.find("%%EOF", pdf_bytes.size() - 64), std::string::npos);
  if (shell("command -v pdfinfo").status == 0) {
    const Shell info = shell("pdfinfo " + pdf.string());
    ASSERT_EQ(info.status, 0) << info.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(info.out, m, std::regex(R"(Pages:\s+(\d+))"))) << info.out;
    EXPECT_GE(std::stoi(m[1]), 1);
    // A4 is 595.28 × 841.89 pt (210 × 297 mm): the print stylesheet's @page size.
    EXPECT_NE(info.out.find("(A4)"), std::string::npos) << info.out;
  }
}

std::size_t count_images(const std::string& page) {
  std::size_t images = 0;
  for (std::size_t at = page.find("<img "); at != std::string::npos; at = page.find("<img ", at + 1)) ++images;
  return images;
}

TEST(ReportInBrowser, EveryFigureLoadsAndThePagePrintsToPdf) {
  const std::string exe = chromium();
  if (exe.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  if (shell("command -v gnuplot").status != 0)
    GTEST_SKIP() << "gnuplot is not installed: the report would have no figures";

  const fs::path dir = test::scratch_dir("report_browser");
  test::write_file(dir / "experiment.toml", test::small_experiment());
  auto r = test::run_tricot("synth " + (dir / "experiment.toml").string() + " -o " + (dir / "exp").string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  test::write_file(dir / "project.toml", test::small_project("exp"));
  r = test::run_tricot("identify " + (dir / "project.toml").string() + " -o " + (dir / "out").string() + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path html = dir / "out" / "report.html";
  ASSERT_TRUE(fs::exists(html));
  ASSERT_TRUE(fs::exists(dir / "out" / "report.json"));

  // The figures the page embeds: the LM history, the fit of the one test, its field residual map and
  // the eq. 9 surface.
  const std::size_t images = count_images(io::read_text(html));
  EXPECT_EQ(images, 4u);

  check_in_browser(exe, dir, html, images, dir / "report.png", 4600);
}

// The demo's report (issue 13): the reduced chain (two tests, small images, two LM iterations) adds
// the DIC quality, the synchronisation, Tables 4 and 5 and the wall time per stage to the report of
// its identification. Screenshot: build/scratch/report_browser_demo/report.png.
TEST(ReportInBrowser, TheDemoReportShowsTheChainAndPrintsToPdf) {
  const std::string exe = chromium();
  if (exe.empty()) GTEST_SKIP() << "chromium is not installed (scripts/install-deps installs it)";
  if (shell("command -v gnuplot").status != 0)
    GTEST_SKIP() << "gnuplot is not installed: the report would have no figures";

  const fs::path dir = test::scratch_dir("report_browser_demo");
  const auto r = test::run_tricot("demo --small -q -o " + (dir / "demo").string());
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 4) << r.err;  // two LM iterations need not converge
  EXPECT_NE(r.out.find("report: "), std::string::npos) << r.out;
  const fs::path html = dir / "demo" / "identify" / "report.html";
  ASSERT_TRUE(fs::exists(html));
  const std::string page = io::read_text(html);
  for (const char* section : {"DIC quality per test", "Synchronisation of the load cell", "Table 4", "Table 5",
                              "Wall and CPU time per stage", "1/5 render", "s110-wale-040", "s110-course-030"})
    EXPECT_NE(page.find(section), std::string::npos) << section;
  const std::string json = io::read_text(dir / "demo" / "identify" / "report.json");
  for (const char* figure :
       {"plots/dic_quality.png", "plots/sync.png", "plots/history.png", "plots/eq9_course.png", "plots/eq9_wale.png"})
    EXPECT_NE(json.find(figure), std::string::npos) << figure;
  check_in_browser(exe, dir, html, count_images(page), dir / "report.png", 9000);
}

}  // namespace
}  // namespace tricot::project
