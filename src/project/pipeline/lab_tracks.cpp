// Point tracks made by other tools → a test's steps and field (see lab_tracks.hpp).
#include "tricot/project/lab_tracks.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "tricot/core/error.hpp"
#include "tricot/io/log.hpp"

namespace tricot::project {

namespace fs = std::filesystem;

namespace {

std::string num(double v) { return fmt::format("{:.9g}", v); }

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The header line of a table: the line before its first data row.
int header_line(const io::LogTable& t) { return t.lines.empty() ? 0 : t.lines.front() - 1; }

// A column's unit, px or mm: from its brackets (`x [px]`) or a _px / _mm suffix (`x_px`); "" when none.
std::string unit_of(const std::string& header) {
  const auto [name, unit] = io::split_unit(header);
  const std::string u = lower(unit);
  if (u == "px" || u == "pixel" || u == "pixels" || u == "pix") return "px";
  if (u == "mm") return "mm";
  const std::string n = lower(name);
  if (n.size() > 3 && (n.ends_with("_px") || n.ends_with(" px") || n.ends_with(".px"))) return "px";
  if (n.size() > 3 && (n.ends_with("_mm") || n.ends_with(" mm") || n.ends_with(".mm"))) return "mm";
  return "";
}

// Every column's unit must agree with the others and with tracks_unit: one line at the header.
std::string check_units(const io::LogTable& t, const std::vector<std::size_t>& columns, const LabTestSpec& test,
                        const char* key) {
  const std::string& given = test.tracks_unit;
  std::string seen, seen_column;
  for (std::size_t c : columns) {
    const std::string u = unit_of(t.columns[c]);
    if (u.empty()) continue;
    if (!seen.empty() && u != seen)
      throw InputError({t.file, header_line(t), key},
                       fmt::format("positions in px and mm mixed: column '{}' is in {}, column '{}' in {}", seen_column,
                                   seen, t.columns[c], u),
                       t.columns[c], "every position column in one unit");
    seen = u, seen_column = t.columns[c];
  }
  if (!seen.empty() && test.tracks_unit_given && seen != given) {
    const Location at = test.origin.where("tracks_unit");
    throw InputError({t.file, header_line(t), key},
                     fmt::format("column '{}' is in {}, but tracks_unit = \"{}\" ({})", seen_column, seen, given,
                                 at.file + ":" + std::to_string(at.line)),
                     seen, given);
  }
  return seen.empty() ? given : seen;
}

long frame_of(double v, const io::LogTable& t, std::size_t row, const std::string& column) {
  if (!(v >= 0) || v != std::floor(v) || v > 1e12)
    throw InputError({t.file, t.lines[row], column}, "a frame is a whole number ≥ 0", num(v), "0, 1, 2, …");
  return static_cast<long>(v);
}

PointTracks read_long(const LabTestSpec& test, const fs::path& file) {
  const io::LogTable t = io::read_log(file);
  const std::string &fc = test.frame_column, &pc = test.point_column;
  const std::string &xc = test.x_column, &yc = test.y_column;
  PointTracks r;
  r.file = file.string();
  r.unit = check_units(t, {t.column(xc), t.column(yc)}, test, "x_column");
  const auto frame = t.numbers(fc);
  const auto point = t.text(pc);
  // An empty position cell is a point the tool lost in that frame (`tricot dic`'s specimen.csv writes so).
  const auto x = t.numbers_or_empty(xc), y = t.numbers_or_empty(yc);
  std::map<long, std::size_t> frame_index;
  std::map<std::string, std::size_t> point_index;
  std::vector<std::map<std::size_t, Vec2>> rows;
  for (std::size_t i = 0; i < t.rows(); ++i) {
    const long f = frame_of(frame[i], t, i, fc);
    auto [fi, new_frame] = frame_index.try_emplace(f, rows.size());
    if (new_frame) {
      rows.emplace_back();
      r.frames.push_back(f);
      r.lines.push_back(t.lines[i]);
    }
    if (point[i].empty()) throw InputError({t.file, t.lines[i], pc}, "an empty point name", "\"\"", "a name");
    auto [pi, new_point] = point_index.try_emplace(point[i], r.points.size());
    if (new_point) r.points.push_back(point[i]);
    if (!rows[fi->second].emplace(pi->second, Vec2(x[i], y[i])).second)
      throw InputError({t.file, t.lines[i], pc}, fmt::format("point '{}' is given twice in frame {}", point[i], f),
                       point[i], "each point once per frame");
  }
  if (r.frames.empty()) throw InputError({t.file, 0, fc}, "no frame", "0 rows", "one row per point and frame");
  // Frames in file order must increase: a track file is a sequence.
  for (std::size_t k = 1; k < r.frames.size(); ++k)
    if (r.frames[k] <= r.frames[k - 1])
      throw InputError({t.file, r.lines[k], fc},
                       fmt::format("frame {} comes after frame {}", r.frames[k], r.frames[k - 1]),
                       std::to_string(r.frames[k]), "increasing frames");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    std::vector<Vec2> pos(r.points.size(), Vec2::Constant(NAN));
    for (std::size_t p = 0; p < r.points.size(); ++p) {
      const auto it = rows[k].find(p);
      if (it == rows[k].end())
        throw InputError(
            {t.file, r.lines[k], pc},
            fmt::format("frame {} has no point '{}' (a point missing from a frame)", r.frames[k], r.points[p]),
            fmt::format("{} of {} points", rows[k].size(), r.points.size()), "every point in every frame");
      pos[p] = it->second;
    }
    r.x.push_back(std::move(pos));
  }
  return r;
}

PointTracks read_wide(const LabTestSpec& test, const fs::path& file) {
  const io::LogTable t = io::read_log(file);
  const std::string& fc = test.frame_column;
  const std::size_t frame_col = t.column(fc);
  PointTracks r;
  r.file = file.string();
  // <point>_x and <point>_y, a unit allowed after them.
  std::map<std::string, std::pair<std::size_t, std::size_t>> cols;  // point → (x column, y column)
  std::vector<std::size_t> position_columns;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    if (c == frame_col) continue;
    std::string name = lower(io::split_unit(t.columns[c]).first);
    while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
    for (const char* u : {"_px", " px", ".px", "_mm", " mm", ".mm"})
      if (name.size() > 3 && name.ends_with(u)) name.resize(name.size() - 3);
    if (name.size() < 3 || (name.back() != 'x' && name.back() != 'y') ||
        !(name[name.size() - 2] == '_' || name[name.size() - 2] == ' ' || name[name.size() - 2] == '.'))
      throw InputError({t.file, header_line(t), t.columns[c]}, "a wide track table's column is <point>_x or <point>_y",
                       t.columns[c], "frame, then <point>_x, <point>_y for each point");
    const std::string point = io::split_unit(t.columns[c]).first.substr(0, name.size() - 2);
    auto [it, fresh] = cols.try_emplace(point, t.columns.size(), t.columns.size());
    if (fresh) r.points.push_back(point);
    (name.back() == 'x' ? it->second.first : it->second.second) = c;
    position_columns.push_back(c);
  }
  for (const auto& p : r.points)
    if (cols[p].first == t.columns.size() || cols[p].second == t.columns.size())
      throw InputError({t.file, header_line(t), p},
                       fmt::format("point '{}' has only one of its columns {}_x, {}_y", p, p, p), p, "both");
  r.unit = check_units(t, position_columns, test, "tracks");
  const auto frame = t.numbers(fc);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    r.frames.push_back(frame_of(frame[i], t, i, fc));
    r.lines.push_back(t.lines[i]);
    if (i > 0 && r.frames[i] <= r.frames[i - 1])
      throw InputError({t.file, t.lines[i], fc},
                       fmt::format("frame {} comes after frame {}", r.frames[i], r.frames[i - 1]),
                       std::to_string(r.frames[i]), "increasing frames, each once");
  }
  r.x.assign(t.rows(), std::vector<Vec2>(r.points.size()));
  for (std::size_t p = 0; p < r.points.size(); ++p) {
    const auto [cx, cy] = cols[r.points[p]];
    for (const std::size_t c : {cx, cy}) {
      const auto values = t.numbers_or_empty(t.columns[c]);  // text in a cell: its own error
      for (std::size_t i = 0; i < t.rows(); ++i) {
        if (!std::isfinite(values[i]))
          throw InputError({t.file, t.lines[i], t.columns[c]},
                           fmt::format("frame {} has no position of point '{}' (a point missing from a frame)",
                                       r.frames[i], r.points[p]),
                           "\"\"", "a number in every frame");
        r.x[i][p](c == cx ? 0 : 1) = values[i];
      }
    }
  }
  return r;
}

// DICe: one DICe_solution_NNNN.txt per frame.
PointTracks read_dice(const LabTestSpec& test, const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw FileError(test.origin.where("tracks"), "tracks_format = \"dice\" needs the folder of DICe's results",
                    folder.string());
  std::vector<std::pair<long, fs::path>> files;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string n = e.path().filename().string();
    if (!n.starts_with("DICe_solution_") || e.path().extension() != ".txt") continue;
    const std::string digits = e.path().stem().string().substr(14);
    if (digits.empty() || !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    files.emplace_back(std::stol(digits), e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.size() < 2)
    throw FileError(test.origin.where("tracks"),
                    fmt::format("{} DICe_solution_NNNN.txt files: a sequence needs at least 2", files.size()),
                    folder.string());
  PointTracks r;
  r.file = folder.string();
  r.unit = "px";  // LabSpec::validate() refuses another tracks_unit
  std::map<long, std::size_t> point_index;
  for (const auto& [frame, file] : files) {
    const io::LogTable t = io::read_log(file);
    const auto id = t.numbers("SUBSET_ID");
    const auto X = t.numbers("COORDINATE_X"), Y = t.numbers("COORDINATE_Y");
    const auto u = t.numbers("DISPLACEMENT_X"), v = t.numbers("DISPLACEMENT_Y");
    std::vector<double> sigma(t.rows(), 0.0);
    if (t.has_column("SIGMA")) sigma = t.numbers("SIGMA");
    std::vector<Vec2> pos(point_index.size(), Vec2::Constant(NAN));
    for (std::size_t i = 0; i < t.rows(); ++i) {
      const long p = static_cast<long>(id[i]);
      auto [it, fresh] = point_index.try_emplace(p, r.points.size());
      if (fresh) {
        r.points.push_back(std::to_string(p));
        for (auto& row : r.x) row.push_back(Vec2::Constant(NAN));
        pos.push_back(Vec2::Constant(NAN));
      }
      if (sigma[i] >= 0) pos[it->second] = Vec2(X[i] + u[i], Y[i] + v[i]);  // SIGMA = −1: lost in this frame
    }
    r.frames.push_back(frame);
    r.lines.push_back(0);
    r.x.push_back(std::move(pos));
  }
  return r;
}

}  // namespace

std::size_t PointTracks::find(const std::string& point) const {
  return static_cast<std::size_t>(std::find(points.begin(), points.end(), point) - points.begin());
}

PointTracks read_point_tracks(const LabTestSpec& test) {
  const fs::path& file = test.tracks;
  if (test.tracks_format == "dice") return read_dice(test, file);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw FileError(test.origin.where("tracks"), "track file not found", file.string());
  return test.tracks_format == "wide" ? read_wide(test, file) : read_long(test, file);
}

FrameForces read_frame_forces(const LabTestSpec& test) {
  const fs::path& file = test.frame_forces;
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw FileError(test.origin.where("frame_forces"), "force file not found", file.string());
  const io::LogTable t = io::read_log(file);
  const std::string& fc = test.frame_column;
  FrameForces f;
  f.file = file.string();
  const auto frame = t.numbers(fc);
  f.force_N = t.numbers(test.force_column);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    f.frames.push_back(frame_of(frame[i], t, i, fc));
    f.lines.push_back(t.lines[i]);
    if (i > 0 && f.frames[i] <= f.frames[i - 1])
      throw InputError({t.file, t.lines[i], fc},
                       fmt::format("frame {} comes after frame {}", f.frames[i], f.frames[i - 1]),
                       std::to_string(f.frames[i]), "increasing frames, each once");
  }
  return f;
}

TracksTest tracks_test(const LabTestSpec& test, const LabPhysicalSpec& physical, bool full) {
  const PointTracks tracks = read_point_tracks(test);
  const FrameForces forces = read_frame_forces(test);

  // Synchronised by frame number: the same frames in both files.
  for (std::size_t k = 0; k < std::max(tracks.frames.size(), forces.frames.size()); ++k) {
    const bool in_tracks = k < tracks.frames.size(), in_forces = k < forces.frames.size();
    if (in_tracks && in_forces && tracks.frames[k] == forces.frames[k]) continue;
    if (in_forces && (!in_tracks || forces.frames[k] < tracks.frames[k]))
      throw InputError(
          {forces.file, forces.lines[k], test.frame_column},
          fmt::format("frame {} is not in the tracks ({}): the force file's frames do not match the tracks'",
                      forces.frames[k], tracks.file),
          std::to_string(forces.frames[k]), in_tracks ? "frame " + std::to_string(tracks.frames[k]) : "no more frames");
    throw InputError(
        {forces.file, in_forces ? forces.lines[k] : (forces.lines.empty() ? 0 : forces.lines.back() + 1),
         test.frame_column},
        fmt::format("no force for the tracks' frame {} ({}{}): the force file's frames do not match the tracks'",
                    tracks.frames[k], tracks.file, tracks.lines[k] > 0 ? ":" + std::to_string(tracks.lines[k]) : ""),
        in_forces ? "frame " + std::to_string(forces.frames[k]) : "no more rows",
        "frame " + std::to_string(tracks.frames[k]));
  }

  TracksTest out;
  // The scale: the test's own, else the lab file's camera; tracks in mm need none.
  if (tracks.unit == "mm") {
    out.mm_per_px = 1;
  } else if (test.mm_per_px > 0) {
    out.mm_per_px = test.mm_per_px;
  } else if (physical.mm_per_px > 0) {
    out.mm_per_px = physical.mm_per_px;
  } else {
    test.origin.fail("mm_per_px", "tracks in px need the test's scale (or [physical] mm_per_px)", "0", "mm_per_px > 0");
  }
  dic::PhysicalFrame frame;
  frame.mm_per_px = out.mm_per_px;
  frame.angle_deg = physical.angle_deg;
  frame.y_up = physical.y_up;
  // A full specimen's tracks in mm are points of the mesh frame as they stand.
  const bool mesh_frame = full && tracks.unit == "mm";
  if (mesh_frame) frame.angle_deg = 0, frame.y_up = false;

  // The clamps: the pull's two ends.
  const io::Strings& clamps = test.clamps;
  std::size_t ca = tracks.points.size(), cb = ca;
  if (!clamps.empty()) {
    ca = tracks.find(clamps[0]), cb = tracks.find(clamps[1]);
    for (std::size_t i = 0; i < 2; ++i)
      if ((i == 0 ? ca : cb) == tracks.points.size())
        test.origin.fail("clamps", fmt::format("'{}' is not a tracked point of {}", clamps[i], tracks.file), clamps[i],
                         fmt::format("one of {}", fmt::join(tracks.points, ", ")));
    for (std::size_t k = 0; k < tracks.frames.size(); ++k)
      if (!tracks.x[k][ca].allFinite() || !tracks.x[k][cb].allFinite())
        test.origin.fail("clamps", fmt::format("a clamp marker is lost in frame {}", tracks.frames[k]), "",
                         "both clamps in every frame");
  }
  const std::vector<Vec2>& x0 = tracks.x.front();
  const Vec2 centre = !clamps.empty() ? Vec2(0.5 * (x0[ca] + x0[cb])) : Vec2::Zero();
  if (mesh_frame) {
    frame.centre_px = Vec2::Zero();
  } else if (clamps.empty()) {
    const io::Reals& c = physical.centre_px;
    if (c.size() != 2)
      physical.origin.fail("centre_px",
                           "point tracks without clamps need the specimen centre (or give the test's clamps)",
                           std::to_string(c.size()) + " numbers", "[x, y]");
    frame.centre_px = {c[0], c[1]};
  } else {
    frame.centre_px = centre;
  }
  frame.validate();

  // The clamps' distance along the pull, mm, per frame: a clamp marker that does not move is an error.
  std::vector<double> distance(tracks.frames.size(), 0.0);
  if (!clamps.empty()) {
    double change = 0;
    for (std::size_t k = 0; k < distance.size(); ++k) {
      distance[k] = std::abs(frame.vector(tracks.x[k][cb] - tracks.x[k][ca])(1));
      change = std::max(change, std::abs(distance[k] - distance[0]));
    }
    if (!(distance[0] > 0))
      test.origin.fail("clamps", "the two clamp markers lie on one line across the pull",
                       fmt::format("{}", fmt::join(clamps, ", ")), "one at each end of the specimen");
    if (change < 0.01 * distance[0]) {
      // Name the marker that moves least.
      double move_a = 0, move_b = 0;
      for (std::size_t k = 0; k < distance.size(); ++k)
        move_a = std::max(move_a, frame.vector(tracks.x[k][ca] - x0[ca]).norm()),
        move_b = std::max(move_b, frame.vector(tracks.x[k][cb] - x0[cb]).norm());
      const std::string& still = move_a < move_b ? clamps[0] : clamps[1];
      test.origin.fail(
          "clamps",
          fmt::format("clamp marker '{}' does not move against the other: their distance changes by {} mm at most "
                      "over {} frames ({} of {} mm)",
                      still, num(change), distance.size(), num(change / distance[0] * 100) + " %", num(distance[0])),
          still, "a pulled clamp: the distance changes by ≥ 1 %");
    }
  }

  // The geometry: the free length is the clamps' distance unless given.
  out.geometry.width_mm = test.width_mm;
  out.geometry.free_length_mm = !clamps.empty() && !test.free_length_mm_given ? distance[0] : test.free_length_mm;
  out.geometry.tolerance_mm = test.tolerance_mm;

  // A full model's frame is the clamps' midpoint unless the tracks are in the mesh frame already.
  out.centred_on_clamps = full && !clamps.empty() && !mesh_frame;

  // Rigid motion: the clamps' mean displacement, px (or mm), per frame.
  out.rigid_motion_removed = !full && !clamps.empty();
  std::vector<Vec2> rigid(tracks.frames.size(), Vec2::Zero());
  if (out.rigid_motion_removed)
    for (std::size_t k = 0; k < rigid.size(); ++k) rigid[k] = 0.5 * (tracks.x[k][ca] + tracks.x[k][cb]) - centre;

  // The steps: every frame_stride-th frame after the reference, and the last.
  const auto stride = static_cast<std::size_t>(test.frame_stride);
  std::vector<std::size_t> step_index;
  for (std::size_t k = stride; k < tracks.frames.size(); k += stride) step_index.push_back(k);
  if (step_index.empty() || step_index.back() != tracks.frames.size() - 1)
    if (tracks.frames.size() > 1) step_index.push_back(tracks.frames.size() - 1);
  if (step_index.empty())
    test.origin.fail("tracks", "one frame only: a test needs a reference and at least one step", tracks.file);
  out.reference_frame = tracks.frames.front();

  // The field points: `points`, or every point but the clamps.
  std::vector<std::size_t> field_points;
  if (!test.points.empty()) {
    for (const std::string& p : test.points) {
      const std::size_t i = tracks.find(p);
      if (i == tracks.points.size())
        test.origin.fail("points", fmt::format("'{}' is not a tracked point of {}", p, tracks.file), p,
                         fmt::format("one of {}", fmt::join(tracks.points, ", ")));
      field_points.push_back(i);
    }
  } else {
    for (std::size_t i = 0; i < tracks.points.size(); ++i)
      if (i != ca && i != cb) field_points.push_back(i);
  }
  lab::QuarterField& q = out.field;
  q.kind = lab::FieldKind::cumulative;
  std::vector<Vec2> P0, sign;
  for (std::size_t i : field_points) {
    bool complete = tracks.x[0][i].allFinite();
    for (std::size_t k : step_index) complete = complete && tracks.x[k][i].allFinite();
    if (!complete) {
      ++q.incomplete;
      continue;
    }
    const Vec2 P = frame.point(tracks.x[0][i]);
    // The quarter model folds every point into X, Y ≥ 0 and keeps those inside the rectangle; the full
    // one takes them where they are (identify refuses a point off its mesh, naming it).
    // A full model between clamps is the width × free length rectangle about their midpoint: the
    // points beyond it are left out as the quarter's are.
    const Vec2 X = full ? P : Vec2(P.cwiseAbs());
    const bool rectangle = !full || out.centred_on_clamps;
    if (rectangle && (std::abs(X(0)) > out.geometry.half_width() + out.geometry.tolerance_mm ||
                      std::abs(X(1)) > out.geometry.half_length() + out.geometry.tolerance_mm)) {
      ++q.outside;
      continue;
    }
    q.point_ids.push_back(static_cast<int>(i));
    q.X.push_back(X);
    P0.push_back(P);
    sign.push_back(full ? Vec2(1, 1) : Vec2(P(0) < 0 ? -1 : 1, P(1) < 0 ? -1 : 1));
  }
  const auto steps = static_cast<Eigen::Index>(step_index.size());
  const auto n = static_cast<Eigen::Index>(q.point_ids.size());
  q.u.resize(steps, n), q.v.resize(steps, n), q.sigma_u.resize(steps, n), q.sigma_v.resize(steps, n);
  const double sigma_mm = test.sigma_tracks * (tracks.unit == "mm" ? 1.0 : out.mm_per_px);
  for (Eigen::Index s = 0; s < steps; ++s) {
    const std::size_t k = step_index[std::size_t(s)];
    for (Eigen::Index a = 0; a < n; ++a) {
      const std::size_t i = std::size_t(q.point_ids[std::size_t(a)]);
      const Vec2 u = (frame.point(tracks.x[k][i] - rigid[k]) - P0[std::size_t(a)]).cwiseProduct(sign[std::size_t(a)]);
      q.u(s, a) = u(0), q.v(s, a) = u(1), q.sigma_u(s, a) = sigma_mm, q.sigma_v(s, a) = sigma_mm;
    }
  }
  q.report =
      full && !out.centred_on_clamps
          ? fmt::format("{} of {} points kept in the mesh frame; {} not tracked in every step", n, field_points.size(),
                        q.incomplete)
          : fmt::format("{} of {} points kept; {} outside the {:g} × {:g} mm specimen, {} not tracked in every step", n,
                        field_points.size(), q.outside, out.geometry.width_mm, out.geometry.free_length_mm,
                        q.incomplete);

  // The steps' loads and forces.
  const double tare = test.tare_N.value_or(0.0);
  const double fps = test.fps;
  for (std::size_t s = 0; s < step_index.size(); ++s) {
    const std::size_t k = step_index[s];
    lab::ForceStep f;
    f.step = static_cast<int>(s) + 1;
    f.time_s = double(tracks.frames[k] - tracks.frames[0]) / (fps > 0 ? fps : 1.0);
    f.grip_mm = clamps.empty() ? 0.0 : 0.5 * (distance[k] - distance[0]);
    f.force_N = forces.force_N[k] - tare;
    f.force_per_width = f.force_N / out.geometry.width_mm;
    out.steps.push_back(f);
    out.step_frames.push_back(tracks.frames[k]);
  }
  // The full model's clamps move as their markers: each one's displacement per step, mm.
  if (full && !clamps.empty())
    for (std::size_t c : {ca, cb}) {
      TracksTest::ClampMotion m{tracks.points[c], {}};
      for (std::size_t k : step_index) m.u.push_back(frame.vector(tracks.x[k][c] - x0[c]));
      out.clamp_motion.push_back(std::move(m));
    }
  if (clamps.empty() && !full) {  // no clamps: the grip from the field (as a DIC test's)
    const auto grip = lab::grip_from_field(q, out.geometry);
    for (std::size_t s = 0; s < out.steps.size(); ++s) out.steps[s].grip_mm = grip[s];
  }
  out.report = fmt::format("{} frames ({} to {}), {} steps (every {} frame(s)), {}", tracks.frames.size(),
                           tracks.frames.front(), tracks.frames.back(), out.steps.size(), stride, q.report);
  return out;
}

}  // namespace tricot::project
