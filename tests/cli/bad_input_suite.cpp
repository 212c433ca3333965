// The bad-input suite (issue 14, part A): hundreds of malformed inputs across the verbs, each run
// through the whole program in-process (tricot_cli_main, what the `tricot` binary's main() calls: one
// process start instead of ~500 keeps the suite to seconds), each asserting the documented exit code (2 config/usage, 3
// file missing or unreadable, 4 not converged) and that stderr is exactly one line in the contract form
// `tricot: error: FILE:LINE: KEY: …` naming the right file, line and key (docs/design.md "Exit codes").
//
// The table is built in code from tiny inputs (a 2 × 4 Q4 mesh, 3 steps, 64 × 64 px images), so that a
// case fails in milliseconds: every input here is refused before any expensive work. Part of it is
// generated from the verbs' own schemas: every key of every config file given a value of the wrong
// type, and every bounded number given one out of its range. The rest is written by hand: CSV, JSON and
// log files, images, flags and folders, with one case (at least) for each of the 13 findings of the
// issue (names starting with `Issue14_`).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "testing/paths.hpp"
#include "verbs.hpp"
#include "tricot/image/image.hpp"
#include "tricot/io/config.hpp"
#include "tricot/project/case_spec.hpp"
#include "tricot/project/dic_spec.hpp"
#include "tricot/project/identification.hpp"
#include "tricot/project/lab_experiment.hpp"
#include "tricot/project/synthesis.hpp"
#include "tricot/synth/speckle.hpp"

namespace {

using namespace tricot;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------
// A case and how it runs

/// Files of a case, relative to its folder. Content "/" makes a folder; a key "-" + path removes it.
using Files = std::map<std::string, std::string>;

struct Case {
  std::string name = {};                            ///< the gtest name: letters, digits and _
  Files files = {};                                 ///< written into the case's folder {D}
  std::string args = {};                            ///< after `tricot`; {D} is the case's folder
  int rc = 2;                                       ///< expected exit code
  std::vector<std::string> needles = {};            ///< substrings of the one error line ({D} replaced); rc 0: none
  std::function<void(const fs::path&)> setup = {};  ///< extra setup (images, programs)
  std::string env = {};                             ///< `VAR=value …` put before the program ({D} replaced)
  std::vector<std::string> stdout_has = {};         ///< substrings of stdout
  std::vector<std::string> stdout_lacks = {};       ///< strings stdout must not hold
  std::vector<std::string> absent = {};             ///< paths under {D} that must not exist afterwards
  bool in_dir = false;                              ///< run with {D} as the current folder
};

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_file(const fs::path& p, const std::string& content) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << content;
}

// ---------------------------------------------------------------------------------------------------
// TOML documents as tables of lines, so that a mutation knows the line it lands on

struct Table {
  std::string header;  ///< "[mesh]", "[[test]]", "" for the root
  std::vector<std::string> lines;
};
using Doc = std::vector<Table>;

std::string render(const Doc& d) {
  std::string s;
  for (const Table& t : d) {
    if (!t.header.empty()) s += t.header + "\n";
    for (const auto& l : t.lines) s += l + "\n";
  }
  return s;
}

/// `d` with `key = value` in the table `header` (replaced, or added; the table added at the end when
/// missing). `line` receives the 1-based line of the key in render(result).
Doc with_key(Doc d, const std::string& header, const std::string& key, const std::string& value, int* line) {
  auto t = std::find_if(d.begin(), d.end(), [&](const Table& x) { return x.header == header; });
  if (t == d.end()) {
    d.push_back({header, {}});
    t = d.end() - 1;
  }
  auto l = std::find_if(t->lines.begin(), t->lines.end(),
                        [&](const std::string& x) { return x.rfind(key + " = ", 0) == 0; });
  if (l == t->lines.end()) {
    t->lines.push_back(key + " = " + value);
    l = t->lines.end() - 1;
  } else {
    *l = key + " = " + value;
  }
  int n = 0;
  for (auto x = d.begin(); x != d.end(); ++x) {
    if (!x->header.empty()) ++n;
    if (x == t) {
      n += static_cast<int>(l - t->lines.begin()) + 1;
      break;
    }
    n += static_cast<int>(x->lines.size());
  }
  if (line) *line = n;
  return d;
}

// ---------------------------------------------------------------------------------------------------
// Tiny valid inputs

// The case: a 2 × 4 Q4 strip, Mooney–Rivlin C10, C01, three force steps (30 dofs, a few ms).
Doc case_doc() {
  return {{"[mesh]", {"width = 50.0", "height = 200.0", "element = \"Q4\"", "nx = 2", "ny = 4"}},
          {"[law]", {"type = \"mooney_rivlin\""}},
          {"[law.mooney_rivlin]", {"terms = [\"C10\", \"C01\"]", "values = [0.1, 0.02]"}},
          {"[[test]]",
           {"name = \"tension\"", "kind = \"uniaxial\"", "control = \"force\"", "load_max = 5.0", "steps = 3"}}};
}

Doc synth_doc() {
  Doc d = case_doc();
  d.push_back({"[synth]", {"noise_relative = 0.0", "nx = 2", "ny = 3"}});
  return d;
}

Doc project_doc() {
  Doc d = case_doc();
  d[2].lines[1] = "values = [0.08, 0.025]";
  d.push_back({"[experiment]", {"dir = \"experiment\"", "field_kind = \"cumulative\""}});
  d.push_back({"[[parameter]]", {"name = \"C10\""}});
  d.push_back({"[[parameter]]", {"name = \"C01\""}});
  d.push_back({"[data]", {"edge_displacement = 1.0", "field = 1.0"}});
  return d;
}

// What `tricot synth` writes for synth_doc() (noise-free): identify converges on it in ~10 ms.
const char* kForces =
    "step,load,edge_displacement,edge_force\n"
    "1,1.6666666666666667,4.7525737748018306,1.6666666666666665\n"
    "2,3.3333333333333335,10.051841295107664,3.3333333333333357\n"
    "3,5,15.964512468000757,4.9999999999795115\n";
const char* kField =
    "step,id,x,y,u,v\n"
    "1,1,1,1,-0.023522067293268122,0.048785446487097366\n"
    "1,2,24,1,-0.56493483255922228,0.049031692560690232\n"
    "1,3,1,50,-0.024873433441820549,2.4585572467120751\n"
    "1,4,24,50,-0.57582551373891899,2.4430150006031148\n"
    "1,5,1,99,-0.00092347761632943282,4.71106045273359\n"
    "1,6,24,99,-0.023426515662978899,4.7067596371428388\n"
    "2,1,1,1,-0.047929400690605188,0.10322024176553456\n"
    "2,2,24,1,-1.1506101230610115,0.10369187820570189\n"
    "2,3,1,50,-0.050358447050623589,5.1963227940450505\n"
    "2,4,24,50,-1.1688077041480531,5.1709344912021704\n"
    "2,5,1,99,-0.0018893025741495745,9.9638622308343692\n"
    "2,6,24,99,-0.047853300304607806,9.9555349127403883\n"
    "3,1,1,1,-0.07314757912698705,0.1639860095606131\n"
    "3,2,24,1,-1.7552500213988145,0.16464604364832158\n"
    "3,3,1,50,-0.076376665665117846,8.2467102462062893\n"
    "3,4,24,50,-1.7771491772955916,8.2169615804979834\n"
    "3,5,1,99,-0.0028959215621233931,15.824433034002737\n"
    "3,6,24,99,-0.073228461321683383,15.812443032013261\n";

std::string truth_json(const std::string& noise = "0.0", const std::string& control = "\"force\"",
                       const std::string& steps = "3", const std::string& nx = "2",
                       const std::string& sigma_force = "0.0", const std::string& c10 = "0.1",
                       const std::string& field_kind = "\"cumulative\"") {
  return "{\n  \"law\": \"mooney_rivlin\",\n  \"coefficients\": {\"C10\": " + c10 +
         ", \"C01\": 0.02},\n  \"noise_relative\": " + noise +
         ",\n  \"seed\": 20070101,\n  \"field_kind\": " + field_kind +
         ",\n  \"tests\": [{\"name\": \"tension\", \"control\": " + control +
         ", \"mesh\": {\"element\": \"Q4\", \"width\": 50.0, \"height\": 200.0, \"nx\": " + nx +
         ", \"ny\": 4, \"grading\": 1.0, \"dofs\": 30}, \"steps\": " + steps +
         ", \"points\": 6, \"dropped_points\": 0, \"sigma\": {\"edge_displacement\": 0.0, \"edge_force\": " +
         sigma_force + ", \"field\": 0.0}}]\n}\n";
}

/// The identify case: project.toml and its experiment folder; `over` replaces or adds files.
Files identify_files(Files over = {}, const Doc& project = project_doc()) {
  Files f{{"project.toml", render(project)},
          {"experiment/tension/forces.csv", kForces},
          {"experiment/tension/field.csv", kField}};
  for (auto& [k, v] : over) f[k] = v;
  return f;
}

// A forces.csv / field.csv with one line replaced (1-based; line 1 is the header).
std::string with_line(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out;
  int n = 0;
  for (std::string l; std::getline(in, l);) {
    ++n;
    if (n == line) {
      if (!replacement.empty()) out += replacement + "\n";
    } else {
      out += l + "\n";
    }
  }
  return out;
}

std::string bom_crlf(const std::string& text) { return "\xEF\xBB\xBF" + replace_all(text, "\n", "\r\n"); }

// Speckle frames for dic: 64 × 64 px, each moved by 0.5 px more than the last.
constexpr int kW = 64, kH = 64;

void write_frame(const fs::path& path, double shift, int w = kW, int h = kH) {
  synth::SpeckleOptions o;
  o.subsamples = 1;
  const synth::SpecklePattern P(o, -20, -20, w + 20, h + 20);
  const image::Image img = synth::render(P, w, h, [&](const Vec2& x) { return Vec2(x - Vec2(shift, 0)); });
  write_file(path, image::encode_gray(img, path.extension().string(), 8));
}

void four_frames(const fs::path& d) {
  for (int k = 0; k < 4; ++k) write_frame(d / ("f" + std::to_string(k) + ".png"), 0.5 * k);
}

const std::string kFrames = " {D}/f0.png {D}/f1.png {D}/f2.png {D}/f3.png";

// ---------------------------------------------------------------------------------------------------
// Generated cases: every key of a verb's schema with a value of the wrong type or out of range

struct Verb {
  std::string tag;   ///< test-name prefix
  std::string file;  ///< the config file's name in {D}
  std::string args;  ///< the command, {F} = the config file
  io::SectionSpec schema;
  Doc base;
  Files extra;  ///< other files the verb reads
};

std::string wrong_type(const io::KeySpec& k) {
  if (std::holds_alternative<bool>(k.default_value)) return "\"yes\"";
  if (std::holds_alternative<std::int64_t>(k.default_value)) return "\"7\"";
  if (std::holds_alternative<double>(k.default_value)) return "\"0.5\"";
  if (std::holds_alternative<std::string>(k.default_value)) return k.or_number ? "true" : "12";
  if (std::holds_alternative<io::Reals>(k.default_value)) return "\"1, 2\"";
  return "[1, 2]";
}

/// A value out of the key's range, or "" when it has none that TOML can write.
std::string out_of_range(const io::KeySpec& k) {
  const bool integer = std::holds_alternative<std::int64_t>(k.default_value);
  if (!integer && !std::holds_alternative<double>(k.default_value)) {
    if (std::holds_alternative<std::string>(k.default_value) && !k.choices.empty()) return "\"not_a_choice\"";
    return "";
  }
  auto text = [&](double v) {
    if (integer) return std::to_string(static_cast<long long>(v));
    std::ostringstream s;
    s.precision(17);
    s << v;
    const std::string t = s.str();
    return t.find_first_of(".e") == std::string::npos ? t + ".0" : t;  // TOML: a float needs . or e
  };
  if (std::isfinite(k.max) && k.max < 1e15) return text(integer ? k.max + 1 : k.max * 2 + 1);
  if (std::isfinite(k.min) && k.min > -1e15) return text(k.min - 1);
  return "";
}

std::string sanitize(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

void schema_cases(const Verb& v, const io::SectionSpec& s, const std::string& header, const std::string& path,
                  std::vector<Case>& out) {
  for (const io::KeySpec& k : s.keys) {
    if (header.empty()) continue;  // root keys: none in these schemas
    const std::string dotted = path + "." + k.name;
    for (int mode = 0; mode < 2; ++mode) {
      const std::string value = mode == 0 ? wrong_type(k) : out_of_range(k);
      if (value.empty()) continue;
      int line = 0;
      const Doc d = with_key(v.base, header, k.name, value, &line);
      Case c;
      c.name = v.tag + (mode == 0 ? "_WrongType_" : "_OutOfRange_") + sanitize(dotted);
      c.files = v.extra;
      c.files[v.file] = render(d);
      c.args = replace_all(v.args, "{F}", "{D}/" + v.file);
      c.rc = 2;
      c.needles = {"{D}/" + v.file + ":" + std::to_string(line) + ": " + dotted};
      out.push_back(std::move(c));
    }
  }
  for (const io::SectionSpec& sub : s.sections) {
    const std::string name = path.empty() ? sub.name : path + "." + sub.name;
    const std::string h = sub.array ? "[[" + name + "]]" : "[" + (header.empty() ? sub.name : name) + "]";
    // An array table's entries are named `test[0]`; a sub-table of it `[test.mesh]`, named `test[0].mesh`,
    // and an array inside it `[[test.boundary]]`, named `test[0].boundary[0]`.
    std::string hdr = h, p = sub.array ? name + "[0]" : name;
    if (!header.empty() && header.rfind("[[", 0) == 0) {
      const std::string table = replace_all(replace_all(header, "[[", ""), "]]", "") + "." + sub.name;
      hdr = sub.array ? "[[" + table + "]]" : "[" + table + "]";
      p = path + "." + sub.name + (sub.array ? "[0]" : "");
    }
    // An array of tables that the base file lacks (e.g. [[law.region]]) gets one entry, so that the
    // sub-tables of that entry ([law.region.neo_hookean]) belong to it.
    const bool lacking =
        sub.array && std::none_of(v.base.begin(), v.base.end(), [&](const Table& t) { return t.header == hdr; });
    if (!lacking) {
      schema_cases(v, sub, hdr, p, out);
      continue;
    }
    Verb with_entry = v;
    with_entry.base.push_back({hdr, {}});
    schema_cases(with_entry, sub, hdr, p, out);
  }
}

std::vector<Case> generated_cases() {
  std::vector<Case> out;
  const Doc empty_lab = {{"[[test]]", {"name = \"tension\""}}};
  const std::vector<Verb> verbs = {
      {"Simulate", "case.toml", "simulate {F} -q -o {D}/out", project::case_schema(), case_doc(), {}},
      {"Synth", "experiment.toml", "synth {F} -q -o {D}/out", project::synth_schema(), synth_doc(), {}},
      {"Identify", "project.toml", "identify {F} -q --no-plots -o {D}/out", project::identify_schema(), project_doc(),
       identify_files()},
      {"Dic", "dic.toml", "dic {F} -q -o {D}/out {D}/f0.png {D}/f1.png", project::dic_schema(), Doc{}, {}},
      {"Experiment", "lab.toml", "experiment {F} -q -o {D}/out", project::lab_schema(), empty_lab, {}},
  };
  for (const Verb& v : verbs) schema_cases(v, v.schema, "", "", out);
  // The verbs' schemas share tables (a project is a case plus more): keep each key once per verb, and
  // each table's keys in the verbs that own them, so that the suite stays quick.
  std::vector<Case> kept;
  std::map<std::string, int> seen;
  for (auto& c : out) {
    const std::string tail = c.name.substr(c.name.find('_'));
    const std::string verb = c.name.substr(0, c.name.find('_'));
    if (verb != "Simulate" && seen.count(tail)) continue;
    seen[tail]++;
    kept.push_back(std::move(c));
  }
  return kept;
}

// ---------------------------------------------------------------------------------------------------
// Hand-written cases

std::vector<Case> written_cases() {
  std::vector<Case> v;
  const std::string sim = "simulate {D}/case.toml -q -o {D}/out";
  const Files case_files{{"case.toml", render(case_doc())}};
  const std::string ident = "identify {D}/project.toml -q --no-plots -o {D}/out";
  const std::string forces = "{D}/experiment/tension/forces.csv";
  const std::string field = "{D}/experiment/tension/field.csv";
  const std::string truth = "{D}/experiment/truth.json";
  auto add = [&](Case c) { v.push_back(std::move(c)); };

  // --- Command line (CLI11's errors in the contract's one line) ---------------------------------
  for (const char* verb : {"simulate", "identify", "dic", "synth", "experiment", "relax"}) {
    add({std::string("Cli_") + verb + "_NoArguments", {}, verb, 2, {"command line: " + std::string(verb) + ": "}});
    add({std::string("Cli_") + verb + "_UnknownFlag",
         {},
         std::string(verb) + " x.toml -o y --frobnicate",
         2,
         {"command line: " + std::string(verb) + ": ", "--frobnicate"}});
    add({std::string("Cli_") + verb + "_OutFlagWithoutValue",
         {},
         std::string(verb) + " x.toml -o",
         2,
         {"command line: " + std::string(verb) + ": ", "--out"}});
  }
  add({"Cli_demo_UnknownFlag", {}, "demo --frobnicate", 2, {"command line: demo: ", "--frobnicate"}});
  add({"Cli_demo_BadPrintExample", {}, "demo --print-example nope", 2, {"command line: demo: ", "--print-example"}});
  add({"Cli_UnknownVerb", {}, "frobnicate", 2, {"command line: unknown verb 'frobnicate'"}});
  add({"Cli_NoVerb", {}, "", 2, {"command line: ", "subcommand"}});
  add({"Cli_UnknownTopFlag", {}, "--frobnicate", 2, {"command line: unknown option '--frobnicate'"}});
  add({"Cli_dic_ModeNotAWord", {}, "dic --mode sideways -o {D}/out a.png", 2, {"command line: dic: ", "--mode"}});
  add({"Cli_dic_SubsetNotANumber", {}, "dic --subset big -o {D}/out a.png", 2, {"command line: dic: ", "--subset"}});
  add({"Cli_dic_StepZero", {}, "dic --step 0 -o {D}/out a.png", 2, {"command line: dic: ", "--step"}});
  add({"Cli_relax_MaxTermsNotANumber",
       {},
       "relax log.txt --max-terms many -o {D}/out",
       2,
       {"command line: relax: ", "--max-terms"}});
  add({"Cli_relax_DurationNotANumber",
       {},
       "relax log.txt --duration long -o {D}/out",
       2,
       {"command line: relax: ", "--duration"}});
  add({"Cli_identify_KillAfterNotANumber",
       {},
       "identify p.toml -o {D}/out --kill-after soon",
       2,
       {"command line: identify: ", "soon"}});
  add({"Cli_simulate_TestWithoutName",
       {},
       "simulate c.toml -o {D}/out --test",
       2,
       {"command line: simulate: ", "--test"}});
  add({"Cli_simulate_TwoCaseFiles", {}, "simulate a.toml b.toml -o {D}/out", 2, {"command line: simulate: "}});

  // --- Output folders (issue: -o naming a file; -o '') -----------------------------------------
  add({"Issue14_Simulate_EmptyOutFolder",
       case_files,
       "simulate {D}/case.toml -q -o ''",
       2,
       {"command line: -o: empty output folder"},
       {},
       {},
       {},
       {},
       {"{D}/tension"},
       true});
  add({"Issue14_Identify_OutIsAFile",
       identify_files({{"taken", "x"}}),
       "identify {D}/project.toml -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Issue14_Demo_OutIsAFile",
       {{"taken", "x"}},
       "demo -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Issue14_Demo_OutUnderAFile", {{"taken", "x"}}, "demo -q -o {D}/taken/sub", 3, {"{D}/taken: not a folder"}});
  add({"Demo_EmptyOutFolder", {}, "demo -q -o ''", 2, {"command line: -o: empty output folder"}});
  add({"Simulate_OutIsAFile",
       {{"case.toml", render(case_doc())}, {"taken", "x"}},
       "simulate {D}/case.toml -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Synth_OutIsAFile",
       {{"e.toml", render(synth_doc())}, {"taken", "x"}},
       "synth {D}/e.toml -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Synth_EmptyOutFolder",
       {{"e.toml", render(synth_doc())}},
       "synth {D}/e.toml -q -o ''",
       2,
       {"command line: -o"}});
  add({"Identify_EmptyOutFolder", identify_files(), "identify {D}/project.toml -q -o ''", 2, {"command line: -o"}});
  add({"Dic_OutIsAFile",
       {{"taken", "x"}},
       "dic -q -o {D}/taken" + kFrames,
       3,
       {"{D}/taken: the output folder is a file"},
       four_frames});
  add({"Experiment_OutIsAFile",
       {{"lab.toml", "[[test]]\nname = \"t\"\n"}, {"taken", "x"}},
       "experiment {D}/lab.toml -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Relax_OutIsAFile",
       {{"log.txt", "time,force\n0,1\n"}, {"taken", "x"}},
       "relax {D}/log.txt -q -o {D}/taken",
       3,
       {"{D}/taken: the output folder is a file"}});
  add({"Relax_EmptyOutFolder",
       {{"log.txt", "time,force\n0,1\n"}},
       "relax {D}/log.txt -q -o ''",
       2,
       {"command line: -o"}});

  // --- Config files: missing, folders, syntax, BOM and CRLF ----------------------------------------
  add({"Simulate_MissingCaseFile", {}, sim, 3, {"{D}/case.toml: file not found"}});
  add({"Issue14_Simulate_CaseFileIsAFolder", {{"case.toml", "/"}}, sim, 3, {"{D}/case.toml: is a folder, not a file"}});
  add({"Simulate_CaseFileIsEmpty", {{"case.toml", ""}}, sim, 2, {"{D}/case.toml"}});
  add({"Simulate_TomlSyntaxError",
       {{"case.toml", "[mesh\nnx = 2\n"}},
       sim,
       2,
       {"{D}/case.toml:1: ", "TOML syntax error"}});
  add({"Simulate_UnknownTable",
       {{"case.toml", render(case_doc()) + "[meshh]\nnx = 2\n"}},
       sim,
       2,
       {"{D}/case.toml:", "meshh"}});
  add({"Simulate_UnknownKey",
       {{"case.toml", replace_all(render(case_doc()), "nx = 2", "nxx = 2")}},
       sim,
       2,
       {"{D}/case.toml:5: mesh.nxx: unknown key"}});
  add({"Simulate_DuplicateKey",
       {{"case.toml", replace_all(render(case_doc()), "nx = 2", "nx = 2\nnx = 3")}},
       sim,
       2,
       {"{D}/case.toml:6: ", "TOML syntax error"}});
  Doc no_test = case_doc();
  no_test.pop_back();
  add({"Simulate_NoTest", {{"case.toml", render(no_test)}}, sim, 2, {"{D}/case.toml", "test"}});
  add({"Simulate_TwoTestsOfOneName",
       {{"case.toml", render(case_doc()) + render({case_doc()[3]})}},
       sim,
       2,
       {"{D}/case.toml:", "name"}});
  add({"Simulate_UnknownLaw",
       {{"case.toml", replace_all(render(case_doc()), "type = \"mooney_rivlin\"", "type = \"rubber\"")}},
       sim,
       2,
       {"{D}/case.toml:8: law.type: not a valid choice"}});
  add({"Simulate_TermsAndValuesDiffer",
       {{"case.toml", replace_all(render(case_doc()), "values = [0.1, 0.02]", "values = [0.1]")}},
       sim,
       2,
       {"{D}/case.toml:", "law.mooney_rivlin"}});
  add({"Simulate_LoadsNotIncreasing",
       {{"case.toml", replace_all(render(case_doc()), "load_max = 5.0", "loads = [1.0, 0.5]")}},
       sim,
       2,
       {"{D}/case.toml:", "test[0].loads"}});
  add({"Simulate_SimpleShearUnderForce",
       {{"case.toml", replace_all(render(case_doc()), "kind = \"uniaxial\"", "kind = \"simple_shear\"")}},
       sim,
       2,
       {"{D}/case.toml:", "test[0].control"}});
  add({"Simulate_GuideOnAFreeEdge",
       {{"case.toml", replace_all(render(case_doc()), "steps = 3", "steps = 3\nguide = [1.0]")}},
       sim,
       2,
       {"{D}/case.toml:", "test[0].guide"}});
  add({"Simulate_TestNotInTheCase", case_files, sim + " --test nope", 2, {"nope"}});
  add({"Simulate_NanValue",
       {{"case.toml", replace_all(render(case_doc()), "load_max = 5.0", "load_max = nan")}},
       sim,
       2,
       {"{D}/case.toml:16: test[0].load_max"}});
  add({"Simulate_InfValue",
       {{"case.toml", replace_all(render(case_doc()), "width = 50.0", "width = inf")}},
       sim,
       2,
       {"{D}/case.toml:2: mesh.width"}});
  add({"Issue14_Simulate_BomAndCrlfAreAccepted",
       {{"case.toml", bom_crlf(render(case_doc()))}},
       sim + " --no-vtu",
       0,
       {}});
  add({"Simulate_CrlfIsAccepted",
       {{"case.toml", replace_all(render(case_doc()), "\n", "\r\n")}},
       sim + " --no-vtu",
       0,
       {}});
  add({"Simulate_BomIsAccepted", {{"case.toml", "\xEF\xBB\xBF" + render(case_doc())}}, sim + " --no-vtu", 0, {}});
  add({"Simulate_Utf16IsASyntaxError", {{"case.toml", std::string("\xFF\xFE[\0m\0", 6)}}, sim, 2, {"{D}/case.toml"}});
  add({"Simulate_BinaryFile",
       {{"case.toml", std::string("\x7f"
                                  "ELF\x02\x01\x01\0\0\0",
                                  10)}},
       sim,
       2,
       {"{D}/case.toml"}});

  add({"Simulate_MultiLineStringStaysOneLine",
       {{"case.toml", replace_all(render(case_doc()), "kind = \"uniaxial\"", "kind = \"\"\"uni\naxial\"\"\"")}},
       sim,
       2,
       {"{D}/case.toml:14: test[0].kind"}});
  add({"Simulate_TestNameWithASlash",
       {{"case.toml", replace_all(render(case_doc()), "name = \"tension\"", "name = \"a/b\"")}},
       sim,
       2,
       {"{D}/case.toml:13: test[0].name"}});
  add({"Simulate_TestNameEmpty",
       {{"case.toml", replace_all(render(case_doc()), "name = \"tension\"", "name = \"\"")}},
       sim,
       2,
       {"{D}/case.toml:13: test[0].name"}});

  // --- Resources: a mesh beyond the memory, threads beyond the cores -----------------------------
  {
    int line = 0;
    Doc d = with_key(with_key(case_doc(), "[mesh]", "nx", "2000", nullptr), "[mesh]", "ny", "2000", &line);
    d = with_key(d, "[mesh]", "element", "\"Q8\"", nullptr);
    add({"Issue14_Simulate_MeshBeyondMemoryIsRefusedWithItsSize",
         {{"case.toml", render(d)}},
         sim,
         2,
         {"{D}/case.toml:5: mesh.nx: the mesh does not fit in this machine's memory", "GB"}});
    add({"Issue14_Synth_MeshBeyondMemoryIsRefused",
         {{"e.toml", render(d) + "[synth]\nnx = 2\nny = 3\n"}},
         "synth {D}/e.toml -q -o {D}/out",
         2,
         {"{D}/e.toml:5: mesh.nx: the mesh does not fit"}});
    Doc t = with_key(case_doc(), "[[test]]", "steps", "3", nullptr);
    t.push_back({"[test.mesh]", {"nx = 2000", "ny = 2000", "element = \"Q8\""}});
    add({"Simulate_TestMeshBeyondMemoryIsRefused",
         {{"case.toml", render(t)}},
         sim,
         2,
         {"{D}/case.toml:19: test[0].mesh.nx: the mesh does not fit"}});
  }
  add({"Issue14_Identify_ThreadsBeyondTheCoresRun",
       identify_files({}, with_key(project_doc(), "[identify]", "threads", "1024", nullptr)),
       ident,
       0,
       {}});

  // --- identify: the experiment's CSV files ---------------------------------------------------
  add({"Issue14_Identify_ForcesValueWhoseSquareOverflows",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 4, "3,5,1e200,4.9999999999795115")}}),
       ident,
       2,
       {forces + ":4: edge_displacement: value out of range (got 1e+200"}});
  add({"Identify_ForcesValueTooLarge",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 2, "1,1.6666666666666667,4.75,-2e13")}}),
       ident,
       2,
       {forces + ":2: edge_force: value out of range"}});
  add({"Identify_ForcesMissing",
       identify_files({{"-experiment/tension/forces.csv", ""}}),
       ident,
       3,
       {forces + ": file not found"}});
  add({"Issue14_Identify_ForcesIsAFolder",
       identify_files({{"experiment/tension/forces.csv", "/"}}),
       ident,
       3,
       {forces + ": is a folder, not a file"}});
  add({"Identify_ForcesEmpty",
       identify_files({{"experiment/tension/forces.csv", ""}}),
       ident,
       2,
       {forces + ": empty file"}});
  add({"Identify_ForcesHeaderOnly",
       identify_files({{"experiment/tension/forces.csv", "step,load,edge_displacement\n"}}),
       ident,
       2,
       {forces + ": no steps"}});
  add({"Identify_ForcesWithoutLoad",
       identify_files({{"experiment/tension/forces.csv", replace_all(kForces, "step,load,", "step,lode,")}}),
       ident,
       2,
       {forces + ":1: load: missing column"}});
  add({"Identify_ForcesWithoutStep",
       identify_files({{"experiment/tension/forces.csv", replace_all(kForces, "step,load,", "stp,load,")}}),
       ident,
       2,
       {forces + ":1: step: missing column"}});
  add({"Identify_ForcesWord",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 3, "2,three,10.05,3.33")}}),
       ident,
       2,
       {forces + ":3: load: not a finite number (got \"three\""}});
  add({"Identify_ForcesNan",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 2, "1,1.67,nan,1.67")}}),
       ident,
       2,
       {forces + ":2: edge_displacement: not a finite number"}});
  add({"Identify_ForcesInf",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 4, "3,5,inf,5")}}),
       ident,
       2,
       {forces + ":4: edge_displacement: not a finite number"}});
  add({"Identify_ForcesEmptyCell",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 3, "2,3.33,,3.33")}}),
       ident,
       2,
       {forces + ":3: edge_displacement: not a finite number"}});
  add({"Identify_ForcesRaggedRow",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 3, "2,3.33,10.05")}}),
       ident,
       2,
       {forces + ":3: wrong number of cells"}});
  add({"Identify_ForcesStepNotInteger",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 2, "1.5,1.67,4.75,1.67")}}),
       ident,
       2,
       {forces + ":2: step: not an integer"}});
  add({"Identify_ForcesStepsOutOfOrder",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 3, "3,3.33,10.05,3.33")}}),
       ident,
       2,
       {forces + ":3: step: steps must be numbered"}});
  add({"Identify_ForcesLoadsNotIncreasing",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 3, "2,1.0,10.05,3.33")}}),
       ident,
       2,
       {"the test's loads differ from",
        "from step 2 on"}});  // issue 29: any path in forces.csv; the project's must match it
  add({"Identify_ForcesSemicolons",
       identify_files({{"experiment/tension/forces.csv", replace_all(kForces, ",", ";")}}),
       ident,
       2,
       {forces + ":2: step;load;edge_displacement;edge_force: not a finite number"}});
  add({"Identify_ForcesDecimalComma",
       identify_files({{"experiment/tension/forces.csv", with_line(kForces, 2, "1,\"1,5\",4.75,1.67")}}),
       ident,
       2,
       {forces + ":2: wrong number of cells"}});
  add({"Issue14_Identify_BomAndCrlfCsvAreAccepted",
       identify_files(
           {{"experiment/tension/forces.csv", bom_crlf(kForces)}, {"experiment/tension/field.csv", bom_crlf(kField)}}),
       ident,
       0,
       {}});
  add({"Identify_FieldWord",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 5, "1,4,24,50,left,2.44")}}),
       ident,
       2,
       {field + ":5: u: not a finite number"}});
  add({"Identify_FieldNan",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 6, "1,5,1,99,-0.0009,nan")}}),
       ident,
       2,
       {field + ":6: v: not a finite number"}});
  add({"Identify_FieldValueTooLarge",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 7, "1,6,24,99,1e300,4.7")}}),
       ident,
       2,
       {field + ":7: u: value out of range"}});
  add({"Identify_FieldWithoutId",
       identify_files({{"experiment/tension/field.csv", replace_all(kField, "step,id,", "step,ident,")}}),
       ident,
       2,
       {field + ":1: id: missing column"}});
  add({"Identify_FieldRaggedRow",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 4, "1,3,1,50")}}),
       ident,
       2,
       {field + ":4: wrong number of cells"}});
  add({"Identify_FieldStepOutOfRange",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 2, "9,1,1,1,-0.02,0.05")}}),
       ident,
       2,
       {field + ":2: step: step out of range"}});
  add({"Identify_FieldPointTwice",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 3, "1,1,1,1,-0.02,0.05")}}),
       ident,
       2,
       {field + ":3: id: point 1 appears twice"}});
  add({"Identify_FieldPointMoved",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 8, "2,1,2,1,-0.047,0.103")}}),
       ident,
       2,
       {field + ":8: x: point 1 moved"}});
  add({"Identify_FieldRowMissing",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 19, "")}}),
       ident,
       2,
       {field, "step", "has no row for step 3"}});
  add({"Identify_FieldIdNotInteger",
       identify_files({{"experiment/tension/field.csv", with_line(kField, 2, "1,1.5,1,1,-0.02,0.05")}}),
       ident,
       2,
       {field + ":2: id: not an integer"}});
  add({"Identify_FieldIsAFolder",
       identify_files({{"experiment/tension/field.csv", "/"}}),
       ident,
       3,
       {field + ": is a folder"}});

  // --- identify: truth.json ----------------------------------------------------------------------
  add({"Issue14_Identify_TruthStringWhereANumberBelongs",
       identify_files({{"experiment/truth.json", truth_json("\"0.0\"")}}),
       ident,
       2,
       {truth + ": noise_relative: of the wrong type (got \"0.0\", expected a number)"}});
  add({"Identify_TruthStepsAString",
       identify_files({{"experiment/truth.json", truth_json("0.0", "\"force\"", "\"3\"")}}),
       ident,
       2,
       {truth + ": tests.tension.steps: of the wrong type"}});
  add({"Identify_TruthNxAFraction",
       identify_files({{"experiment/truth.json", truth_json("0.0", "\"force\"", "3", "2.5")}}),
       ident,
       2,
       {truth + ": tests.tension.mesh.nx: of the wrong type"}});
  add({"Identify_TruthSigmaAWord",
       identify_files({{"experiment/truth.json", truth_json("0.0", "\"force\"", "3", "2", "\"none\"")}}),
       ident,
       2,
       {truth + ": tests.tension.sigma.edge_force"}});
  add({"Identify_TruthCoefficientAWord",
       identify_files({{"experiment/truth.json", truth_json("0.0", "\"force\"", "3", "2", "0.0", "\"x\"")}}),
       ident,
       2,
       {truth + ": coefficients.C10: not a number"}});
  add({"Identify_TruthControlANumber",
       identify_files({{"experiment/truth.json", truth_json("0.0", "7")}}),
       ident,
       2,
       {truth + ": tests.tension.control: of the wrong type"}});
  add({"Identify_TruthFieldKindANumber",
       identify_files({{"experiment/truth.json", truth_json("0.0", "\"force\"", "3", "2", "0.0", "0.1", "1")}}),
       ident,
       2,
       {truth + ": field_kind: of the wrong type"}});
  add({"Identify_TruthNotJson",
       identify_files({{"experiment/truth.json", "{\"law\": "}}),
       ident,
       2,
       {truth + ": not valid JSON"}});
  add({"Identify_TruthAnArray", identify_files({{"experiment/truth.json", "[1, 2]"}}), ident, 2, {truth + ": law"}});
  add({"Identify_TruthTestsNotAnArray",
       identify_files({{"experiment/truth.json", "{\"law\": \"x\", \"coefficients\": {}, \"tests\": 3}"}}),
       ident,
       2,
       {truth + ": tests: not an array"}});
  add({"Identify_TruthIsAFolder",
       identify_files({{"experiment/truth.json", "/"}}),
       ident,
       3,
       {truth + ": is a folder"}});
  {
    int line = 0;
    with_key(project_doc(), "[[test]]", "control", "\"displacement\"", &line);
    add({"Issue14_Identify_ControlContradictsTruth",
         identify_files({{"experiment/truth.json", truth_json()}},
                        with_key(project_doc(), "[[test]]", "control", "\"displacement\"", nullptr)),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": test[0].control: contradicts " + truth,
          "(got \"displacement\", expected \"force\")"}});
    with_key(project_doc(), "[experiment]", "field_kind", "\"incremental\"", &line);
    add({"Identify_FieldKindContradictsTruth",
         identify_files({{"experiment/truth.json", truth_json()}},
                        with_key(project_doc(), "[experiment]", "field_kind", "\"incremental\"", nullptr)),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": experiment.field_kind"}});
  }

  // --- identify: the project against its data ---------------------------------------------------
  {
    int line = 0;
    const Doc p = with_key(project_doc(), "[[test]]", "load_max", "5.5", &line);
    add({"Issue14_Identify_LoadsDifferFromTheData",
         identify_files({}, p),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": test[0].load_max: the test's loads differ from " + forces,
          "load 1.83333 at step 1", "load 1.66667 at step 1"}});
    const Doc s = with_key(project_doc(), "[[test]]", "steps", "4", &line);
    add({"Identify_MoreStepsThanTheData",
         identify_files({}, s),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": test[0].steps: the test's loads differ", "got 4 steps",
          "expected 3 steps"}});
    const Doc l = with_key(project_doc(), "[[test]]", "loads", "[1.6666666666666667, 3.3333333333333335, 4.0]", &line);
    add({"Identify_ExplicitLoadsDiffer",
         identify_files({}, l),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": test[0].loads: the test's loads differ", "from step 3 on"}});
    const Doc d = with_key(project_doc(), "[experiment]", "dir", "\"nowhere\"", &line);
    add({"Identify_ExperimentFolderMissing",
         identify_files({}, d),
         ident,
         3,
         {"{D}/project.toml:" + std::to_string(line) + ": experiment.dir: experiment folder not found"}});
    const Doc n = with_key(project_doc(), "[[test]]", "name", "\"shear\"", &line);
    add({"Identify_TestFolderMissing", identify_files({}, n), ident, 3, {"{D}/experiment/shear", "folder not found"}});
    const Doc q = with_key(project_doc(), "[[parameter]]", "name", "\"C99\"", &line);
    add({"Identify_ParameterNotACoefficient", identify_files({}, q), ident, 2, {"{D}/project.toml:", "C99"}});
    const Doc k = with_key(project_doc(), "[[test]]", "kind", "\"simple_shear\"", &line);
    add({"Identify_SimpleShearTest",
         identify_files({}, k),
         ident,
         2,
         {"{D}/project.toml:" + std::to_string(line) + ": test[0]"}});
    const Doc t = with_key(project_doc(), "[experiment]", "sigma_from_truth", "true", &line);
    add({"Identify_SigmaFromTruthWithoutTruth",
         identify_files({}, t),
         ident,
         3,
         {"{D}/project.toml:" + std::to_string(line) + ": experiment.sigma_from_truth"}});
  }
  add({"Identify_ResumeWithoutCheckpoint",
       identify_files(),
       ident + " --resume",
       3,
       {"{D}/out/checkpoint.json", "nothing to resume"}});
  add({"Identify_ProjectIsAFolder", {{"project.toml", "/"}}, ident, 3, {"{D}/project.toml: is a folder"}});
  add({"Identify_ProjectMissing", {}, ident, 3, {"{D}/project.toml: file not found"}});

  // --- dic: images and regions -----------------------------------------------------------------
  const std::string dic = "dic -q -o {D}/out";
  add({"Dic_ImageMissing", {}, dic + kFrames + " {D}/f4.png", 3, {"{D}/f4.png: image not found"}, four_frames});
  add({"Dic_ImageIsAFolder", {{"f4.png", "/"}}, dic + kFrames + " {D}/f4.png", 3, {"{D}/f4.png"}, four_frames});
  add({"Dic_ImageIsText",
       {{"f4.png", "not an image\n"}},
       dic + kFrames + " {D}/f4.png",
       3,
       {"{D}/f4.png"},
       four_frames});
  add({"Issue14_Dic_TruncatedFrameIsFoundBeforeAnyWork",
       {},
       dic + kFrames,
       3,
       {"{D}/f2.png"},
       [](const fs::path& d) {
         four_frames(d);
         const std::string png = slurp(d / "f2.png");
         write_file(d / "f2.png", png.substr(0, png.size() / 3));
       },
       "",
       {},
       {},
       {"{D}/out/points.csv", "{D}/out/overlays"}});
  add({"Issue14_Dic_FrameOfAnotherSizeIsFoundBeforeAnyWork",
       {},
       dic + kFrames,
       3,
       {"{D}/f3.png"},
       [](const fs::path& d) {
         four_frames(d);
         write_frame(d / "f3.png", 1.5, kW + 8, kH);
       },
       "",
       {},
       {},
       {"{D}/out/points.csv", "{D}/out/overlays"}});
  add({"Dic_ReferenceIsText",
       {{"f0.png", "text"}},
       dic + " {D}/f0.png {D}/f1.png",
       3,
       {"{D}/f0.png"},
       [](const fs::path& d) { write_frame(d / "f1.png", 0); }});
  add({"Dic_NoImage", {{"dic.toml", ""}}, dic + " {D}/dic.toml", 2, {"command line: IMAGE: no image given"}});
  add({"Dic_ConfigMissing", {}, dic + " {D}/dic.toml" + kFrames, 3, {"{D}/dic.toml: file not found"}, four_frames});
  add({"Dic_ConfigIsAFolder",
       {{"dic.toml", "/"}},
       dic + " {D}/dic.toml" + kFrames,
       3,
       {"{D}/dic.toml: is a folder"},
       four_frames});
  add({"Dic_SubsetEven", {}, dic + " --subset 12" + kFrames, 2, {"command line: --subset"}, four_frames});
  add({"Dic_SubsetTooSmall", {}, dic + " --subset 3" + kFrames, 2, {"command line: --subset"}, four_frames});
  add({"Dic_RoiThreeNumbers",
       {},
       dic + " --roi 1,2,3" + kFrames,
       2,
       {"command line: --roi: not four numbers"},
       four_frames});
  add({"Dic_RoiWords",
       {},
       dic + " --roi a,b,c,d" + kFrames,
       2,
       {"command line: --roi: not four numbers"},
       four_frames});
  add({"Issue14_Dic_InvertedRoi",
       {},
       dic + " --roi 50,50,10,10" + kFrames,
       2,
       {"command line: --roi: inverted or empty rectangle (got [50, 50, 10, 10]"},
       four_frames});
  add({"Dic_EmptyRoi",
       {},
       dic + " --roi 10,10,10,40" + kFrames,
       2,
       {"command line: --roi: inverted or empty rectangle"},
       four_frames});
  add({"Issue14_Dic_RoiReachingOutOfTheImage",
       {},
       dic + " --roi 0,0,80,40" + kFrames,
       2,
       {"command line: --roi: the rectangle reaches outside the image", "64x64"},
       four_frames});
  add({"Dic_RoiNegative",
       {},
       dic + " --roi -5,0,40,40" + kFrames,
       2,
       {"command line: --roi: the rectangle reaches outside"},
       four_frames});
  add({"Dic_RoiFarOutside",
       {},
       dic + " --roi 500,500,600,600" + kFrames,
       2,
       {"command line: --roi: the rectangle reaches outside"},
       four_frames});
  add({"Issue14_Dic_SeedOutsideTheImage",
       {{"dic.toml", "[dic]\nseeds = [30.0, 30.0, 100.0, 20.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.seeds: seed 2 lies outside the image (got (100, 20)"},
       four_frames});
  add({"Dic_SeedNegative",
       {{"dic.toml", "[dic]\nseeds = [-1.0, 30.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.seeds: seed 1 lies outside"},
       four_frames});
  add({"Dic_SeedsOddCount",
       {{"dic.toml", "[dic]\nseeds = [30.0, 30.0, 20.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.seeds: needs pairs"},
       four_frames});
  add({"Dic_RoiInConfigInverted",
       {{"dic.toml", "[dic]\nroi = [40.0, 10.0, 10.0, 50.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.roi: inverted"},
       four_frames});
  add({"Dic_PolygonVertexOutside",
       {{"dic.toml", "[dic]\nroi_polygon = [0.0, 0.0, 63.0, 0.0, 30.0, 90.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.roi_polygon: vertex 3 lies outside"},
       four_frames});
  add({"Dic_PolygonTwoVertices",
       {{"dic.toml", "[dic]\nroi_polygon = [0.0, 0.0, 63.0, 0.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.roi_polygon: needs at least 3 vertices"},
       four_frames});
  add({"Dic_RoiAndPolygon",
       {{"dic.toml", "[dic]\nroi = [1.0, 1.0, 50.0, 50.0]\nroi_polygon = [0.0, 0.0, 63.0, 0.0, 30.0, 50.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:", "dic.roi: give only one"},
       four_frames});
  add({"Dic_MaskMissing",
       {{"dic.toml", "[dic]\nroi_mask = \"mask.png\"\n"}},
       dic + " {D}/dic.toml" + kFrames,
       3,
       {"{D}/mask.png"},
       four_frames});
  add({"Dic_MaskOfAnotherSize",
       {{"dic.toml", "[dic]\nroi_mask = \"mask.png\"\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.roi_mask: mask image size differs"},
       [](const fs::path& d) {
         four_frames(d);
         write_frame(d / "mask.png", 0, 32, 32);
       }});
  add({"Dic_PhysicalCentreOneNumber",
       {{"dic.toml", "[physical]\nmm_per_px = 0.1\ncentre_px = [1.0]\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:3: physical.centre_px: needs two numbers"},
       four_frames});
  add({"Dic_ConfigSyntaxError",
       {{"dic.toml", "[dic\n"}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:1: ", "TOML syntax error"},
       four_frames});
  add({"Dic_BomAndCrlfConfigAreAccepted",
       {{"dic.toml", bom_crlf("[dic]\nseeds = [100.0, 30.0]\n")}},
       dic + " {D}/dic.toml" + kFrames,
       2,
       {"{D}/dic.toml:2: dic.seeds: seed 1 lies outside"},
       four_frames});

  // --- synth --------------------------------------------------------------------------------------
  const std::string syn = "synth {D}/e.toml -q -o {D}/out";
  add({"Synth_MissingFile", {}, syn, 3, {"{D}/e.toml: file not found"}});
  add({"Synth_FileIsAFolder", {{"e.toml", "/"}}, syn, 3, {"{D}/e.toml: is a folder"}});
  add({"Synth_InsetLeavesNoRoom",
       {{"e.toml", render(with_key(synth_doc(), "[synth]", "inset", "30.0", nullptr))}},
       syn,
       2,
       {"{D}/e.toml:", "synth.inset"}});
  add({"Synth_UnknownSynthKey",
       {{"e.toml", render(with_key(synth_doc(), "[synth]", "noise", "0.1", nullptr))}},
       syn,
       2,
       {"{D}/e.toml:", "synth.noise: unknown key"}});
  add({"Synth_BomAndCrlfAreAccepted", {{"e.toml", bom_crlf(render(synth_doc()))}}, syn, 0, {}});

  // --- experiment (the lab's raw files) ------------------------------------------------------------
  const std::string lab = "experiment {D}/lab.toml -q -o {D}/out";
  const std::string lab_base =
      "[physical]\nmm_per_px = 0.1\n[[test]]\nname = \"tension\"\nimages = \"images\"\nframe_times = \"fps\"\nfps = "
      "2.0\n"
      "log = \"load.txt\"\n";
  add({"Experiment_MissingFile", {}, lab, 3, {"{D}/lab.toml: file not found"}});
  add({"Experiment_FileIsAFolder", {{"lab.toml", "/"}}, lab, 3, {"{D}/lab.toml: is a folder"}});
  add({"Experiment_ImagesFolderMissing",
       {{"lab.toml", lab_base}, {"load.txt", "time,force\n0,0\n1,1\n2,2\n3,3\n4,4\n5,5\n"}},
       lab,
       3,
       {"{D}/images"}});
  add({"Experiment_LogMissing", {{"lab.toml", lab_base}}, lab, 3, {"{D}/"}, four_frames});
  add({"Experiment_NoTest", {{"lab.toml", "[physical]\nmm_per_px = 0.1\n"}}, lab, 2, {"{D}/lab.toml"}});

  // --- relax --------------------------------------------------------------------------------------
  const std::string rel = "relax {D}/log.txt -q -o {D}/out";
  add({"Relax_LogMissing", {}, rel, 3, {"{D}/log.txt: file not found"}});
  add({"Relax_LogIsAFolder", {{"log.txt", "/"}}, rel, 3, {"{D}/log.txt: is a folder"}});
  add({"Relax_LogEmpty", {{"log.txt", ""}}, rel, 2, {"{D}/log.txt"}});
  add({"Relax_LogHeaderOnly", {{"log.txt", "time,force\n"}}, rel, 2, {"{D}/log.txt:1: no data rows"}});
  add({"Relax_NoForceColumn", {{"log.txt", "time,load\n0,1\n1,2\n"}}, rel, 2, {"{D}/log.txt", "force"}});
  add({"Relax_NamedColumnMissing",
       {{"log.txt", "time,force\n0,1\n1,2\n"}},
       rel + " --force Kraft",
       2,
       {"{D}/log.txt", "Kraft"}});
  add({"Relax_MaxTermsZero", {{"log.txt", "time,force\n0,1\n1,2\n"}}, rel + " --max-terms 0", 2, {"max_terms"}});
  add({"Relax_NegativeTolerance", {{"log.txt", "time,force\n0,1\n1,2\n"}}, rel + " --tolerance -1", 2, {"tolerance"}});

  // --- gnuplot: its messages never reach stdout, and an installed one is not called missing -------
  auto fake_gnuplot = [](const fs::path& d) {
    write_file(d / "bin" / "gnuplot",
               "#!/bin/sh\ncat >/dev/null\necho 'line 0: unknown terminal type pngcairo'\nexit 1\n");
    ::chmod((d / "bin" / "gnuplot").c_str(), 0755);
  };
  add({"Issue14_Simulate_GnuplotErrorIsNamedNotPrinted",
       case_files,
       "simulate {D}/case.toml -q -o {D}/out --no-vtu",
       0,
       {},
       fake_gnuplot,
       "PATH={D}/bin:/usr/bin:/bin",
       {"(no plot: gnuplot failed: line 0: unknown terminal type pngcairo)"},
       {"is gnuplot-nox installed", "\nline 0:"}});
  add({"Simulate_MissingGnuplotIsNamed",
       case_files,
       "simulate {D}/case.toml -q -o {D}/out --no-vtu",
       0,
       {},
       [](const fs::path& d) { fs::create_directories(d / "bin"); },
       "PATH={D}/bin",
       {"(no plot: gnuplot is not installed (apt install gnuplot-nox))"}});
  return v;
}

std::vector<Case> all_cases() {
  std::vector<Case> c = written_cases();
  for (auto& g : generated_cases()) c.push_back(std::move(g));
  return c;
}

// ---------------------------------------------------------------------------------------------------
// Running the program in-process: argv from the case's words, stdout and stderr into files

/// Words of a command line: split at spaces, '' quotes kept together (enough for these cases).
std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> w;
  std::string cur;
  bool quoted = false, any = false;
  for (char ch : s) {
    if (ch == '\'') {
      quoted = !quoted, any = true;
    } else if (ch == ' ' && !quoted) {
      if (any) w.push_back(cur);
      cur.clear(), any = false;
    } else {
      cur += ch, any = true;
    }
  }
  if (any) w.push_back(cur);
  return w;
}

struct Outcome {
  int rc = -1;
  std::string out, err;
};

/// Runs `tricot ARGS` as the binary would (tricot_cli_main), with `cwd` as the current folder when
/// given and `env` (`NAME=value`) set meanwhile; its stdout and stderr go through files in `io`.
Outcome run_in_process(const std::string& args, const fs::path& cwd, const std::string& env, const fs::path& io) {
  std::vector<std::string> argv_s = words(args);
  argv_s.insert(argv_s.begin(), "tricot");
  std::vector<char*> argv;
  for (auto& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);

  const fs::path here = fs::current_path();
  if (!cwd.empty()) fs::current_path(cwd);
  std::string env_name, env_old;
  bool had_env = false;
  if (!env.empty()) {
    env_name = env.substr(0, env.find('='));
    if (const char* v = std::getenv(env_name.c_str())) had_env = true, env_old = v;
    ::setenv(env_name.c_str(), env.substr(env.find('=') + 1).c_str(), 1);
  }
  std::fflush(stdout), std::fflush(stderr), std::cout.flush();
  const int saved_out = ::dup(1), saved_err = ::dup(2);
  std::FILE* fo = std::fopen((io / "out").c_str(), "w");
  std::FILE* fe = std::fopen((io / "err").c_str(), "w");
  ::dup2(::fileno(fo), 1), ::dup2(::fileno(fe), 2);
  Outcome r;
  r.rc = tricot_cli_main(static_cast<int>(argv_s.size()), argv.data());
  std::fflush(stdout), std::fflush(stderr), std::cout.flush(), std::cerr.flush();
  ::dup2(saved_out, 1), ::dup2(saved_err, 2);
  ::close(saved_out), ::close(saved_err);
  std::fclose(fo), std::fclose(fe);
  if (!env.empty()) {
    if (had_env) ::setenv(env_name.c_str(), env_old.c_str(), 1);
    else ::unsetenv(env_name.c_str());
  }
  fs::current_path(here);
  r.out = slurp(io / "out");
  r.err = slurp(io / "err");
  return r;
}

// ---------------------------------------------------------------------------------------------------
// The test

class BadInput : public testing::TestWithParam<Case> {};

TEST_P(BadInput, ExitsWithTheDocumentedCodeAndOneContractLineNamingTheInput) {
  const Case& c = GetParam();
  const fs::path d = test::scratch_dir("bad_input/" + c.name);
  const fs::path io = d.parent_path() / (c.name + ".io");
  fs::create_directories(io);
  for (const auto& [path, content] : c.files) {
    if (path[0] == '-') continue;
    if (content == "/") fs::create_directories(d / path);
    else write_file(d / path, content);
  }
  if (c.setup) c.setup(d);
  for (const auto& [path, content] : c.files)
    if (path[0] == '-') fs::remove_all(d / path.substr(1));

  const std::string D = d.string();
  const Outcome r =
      run_in_process(replace_all(c.args, "{D}", D), c.in_dir ? d : fs::path(), replace_all(c.env, "{D}", D), io);
  const int rc = r.rc;
  const std::string &out = r.out, &err = r.err;
  const std::string cmd = "tricot " + replace_all(c.args, "{D}", D);
  fs::remove_all(io);

  EXPECT_EQ(rc, c.rc) << cmd << "\nstderr: " << err;
  if (c.rc == 0) {
    EXPECT_EQ(err, "") << cmd;
  } else {
    const auto lines = std::count(err.begin(), err.end(), '\n');
    EXPECT_EQ(lines, 1) << "stderr must be one line: " << err;
    EXPECT_EQ(err.rfind("tricot: error: ", 0), 0u) << err;
    EXPECT_EQ(err.find("[json.exception"), std::string::npos) << err;
    EXPECT_EQ(err.find("filesystem error"), std::string::npos) << err;
    for (const auto& n : c.needles) {
      const std::string needle = replace_all(n, "{D}", D);
      EXPECT_NE(err.find(needle), std::string::npos) << "missing «" << needle << "» in: " << err;
    }
  }
  for (const auto& s : c.stdout_has) EXPECT_NE(out.find(s), std::string::npos) << "stdout lacks «" << s << "»: " << out;
  for (const auto& s : c.stdout_lacks)
    EXPECT_EQ(out.find(s), std::string::npos) << "stdout holds «" << s << "»: " << out;
  for (const auto& a : c.absent) EXPECT_FALSE(fs::exists(replace_all(a, "{D}", D))) << a << " was written";
}

INSTANTIATE_TEST_SUITE_P(Cases, BadInput, testing::ValuesIn(all_cases()),
                         [](const testing::TestParamInfo<Case>& i) { return i.param.name; });

TEST(BadInputSuite, HoldsAtLeastTwoHundredCasesWithUniqueNamesAndOneForEachFindingOfTheIssue) {
  const std::vector<Case> cases = all_cases();
  EXPECT_GE(cases.size(), 200u);
  std::map<std::string, int> names;
  int issue = 0;
  for (const Case& c : cases) {
    EXPECT_EQ(++names[c.name], 1) << c.name;
    issue += c.name.rfind("Issue14_", 0) == 0;
  }
  EXPECT_GE(issue, 13);
}

}  // namespace
