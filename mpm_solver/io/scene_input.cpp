#include "mpm_solver/io/scene_input.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "common/json_input.hpp"
#include "mpm_solver/core/seeding.hpp"
#include "mpm_solver/io/audit_trail.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm::io {

using common::JsonNode;
using common::Range;

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Vec2 vec2(const JsonNode& node) {
  if (node.array_size("an array [x, y]") != 2) node.fail_expected("an array [x, y]");
  return {node.at(0).number(), node.at(1).number()};
}

// {"L": [[Lxx, Lxy], [Lyx, Lyy]], "origin": [x, y], "normal_stress": {"stress": P, "response_rate": k,
// "integral_time": T}}:
// the whole domain deformed homogeneously, with σ_yy optionally held at −P.
HomogeneousDrive read_homogeneous_drive(const JsonNode& node) {
  node.allow_only({"L", "origin", "normal_stress"});
  const JsonNode rows = node.at("L", "[[Lxx, Lxy], [Lyx, Lyy]]");
  if (rows.array_size("[[Lxx, Lxy], [Lyx, Lyy]]") != 2) rows.fail_expected("[[Lxx, Lxy], [Lyx, Lyy]]");
  HomogeneousDrive drive;
  for (int i = 0; i < 2; ++i) drive.velocity_gradient.row(i) = vec2(rows.at(static_cast<std::size_t>(i))).transpose();
  drive.origin = node.has("origin") ? vec2(node.at("origin", "")) : Vec2::Zero();
  if (const auto control = node.find("normal_stress")) {
    control->allow_only({"stress", "response_rate", "integral_time"});
    NormalStressControl c;
    c.stress = control->number("stress", Range::positive());
    c.response_rate = control->number_or("response_rate", c.response_rate, Range::positive());
    c.integral_time = control->number_or("integral_time", c.integral_time, Range::positive());
    Mat2 rest = drive.velocity_gradient;
    rest(1, 1) = 0;
    if (!(rest.norm() > 0)) rows.fail_expected("a nonzero Lxx, Lxy or Lyx: with normal_stress, Lyy is servoed and bounded by them");
    drive.normal_stress = c;
  }
  return drive;
}

// "apic" | "pic" | {"apic_flip": {"pic_rate": r}} | {"flip_pic": {"pic_rate": r}}, r the PIC
// fraction per second, and in either blend optionally "noise_rate": r_n, that of the rough part
// (default: the larger of 50 and r under APIC-FLIP, r under the FLIP/PIC blend).
VelocityTransfer read_transfer(const JsonNode& node) {
  constexpr std::string_view expected =
      "\"apic\", \"pic\", {\"apic_flip\": {\"pic_rate\": r}} or {\"flip_pic\": {\"pic_rate\": r}} (r >= 0: the "
      "PIC fraction per second; optional \"noise_rate\" >= 0: that of the fluctuations' rough part)";
  VelocityTransfer transfer;
  if (node.value().is_string()) {
    const std::string name = node.string();
    if (name != "apic" && name != "pic") node.fail_expected(expected);
    transfer.kind = name == "apic" ? VelocityTransfer::Kind::apic : VelocityTransfer::Kind::flip_pic;
    transfer.pic_rate = kInfinity;
    transfer.noise_rate.reset();
    return transfer;
  }
  if (!node.value().is_object()) node.fail_expected(expected);
  node.allow_only({"apic_flip", "flip_pic"});
  if (node.value().size() != 1) node.fail_expected(expected);
  const bool affine = node.has("apic_flip");
  const JsonNode blend = node.at(affine ? "apic_flip" : "flip_pic", expected);
  blend.allow_only({"pic_rate", "noise_rate"});
  transfer.kind = affine ? VelocityTransfer::Kind::apic_flip : VelocityTransfer::Kind::flip_pic;
  transfer.pic_rate = blend.number("pic_rate", Range::at_least(0));
  if (blend.has("noise_rate"))
    transfer.noise_rate = blend.number("noise_rate", Range::at_least(0));
  else if (affine)  // never slower than the rest: a faster pic_rate alone still means one blend
    transfer.noise_rate = std::max(VelocityTransfer::kDefaultNoiseRate, transfer.pic_rate);
  else
    transfer.noise_rate.reset();  // the seed's blend: one rate unless asked
  return transfer;
}

std::vector<Vec2> vertices(const JsonNode& node) {
  std::vector<Vec2> out;
  const std::size_t n = node.array_size("an array of [x, y] vertices");
  for (std::size_t k = 0; k < n; ++k) out.push_back(vec2(node.at(k)));
  return out;
}

Grid read_grid(const JsonNode& node) {
  node.allow_only({"origin", "cell_size", "cells"});
  const Vec2 origin = node.has("origin") ? vec2(node.at("origin", "")) : Vec2::Zero();
  const double h = node.number("cell_size", Range::positive());
  const JsonNode cells = node.at("cells", "an array [n_x, n_y] of cell counts");
  if (cells.array_size("an array [n_x, n_y]") != 2) cells.fail_expected("an array [n_x, n_y]");
  const std::int64_t nx = cells.at(0).integer(1, 100000), ny = cells.at(1).integer(1, 100000);
  // Each node holds a few hundred bytes of grid and per-thread transfer buffers: beyond this the run
  // cannot fit in memory, and a scene this size is far past what one machine can step.
  constexpr std::int64_t kMaxCells = 20'000'000;
  if (nx * ny > kMaxCells)
    cells.fail_expected("at most " + std::to_string(kMaxCells) + " cells in all (here n_x * n_y = " +
                        std::to_string(nx * ny) + "; use a coarser cell_size or a smaller domain)");
  return Grid(origin, h, static_cast<int>(nx), static_cast<int>(ny));
}

void read_region(const JsonNode& node, Solver& solver, const std::vector<std::string>& names) {
  node.allow_only({"material", "rectangle", "polygon", "points_per_cell", "velocity"});
  const JsonNode material = node.at("material", "the name of a material");
  const auto it = std::find(names.begin(), names.end(), material.string());
  if (it == names.end()) material.fail_expected("the name of a material");
  if (node.has("rectangle") == node.has("polygon")) node.fail("a region needs exactly one of \"rectangle\" and \"polygon\"");
  Polyline shape;
  if (const auto r = node.find("rectangle")) {
    r->allow_only({"min", "max"});
    const Vec2 lo = vec2(r->at("min", "[x, y]")), hi = vec2(r->at("max", "[x, y]"));
    if (!(lo.array() < hi.array()).all()) r->fail("expected min < max in both directions");
    shape = rectangle(lo, hi);
  } else {
    shape = Polyline{vertices(*node.find("polygon")), true};
  }
  const int ppc = static_cast<int>(node.integer_or("points_per_cell", 2, 1, 16));
  const Vec2 velocity = node.has("velocity") ? vec2(node.at("velocity", "")) : Vec2::Zero();
  const std::size_t added = common::at_node(node, [&] {
    return seed_region(solver, static_cast<std::size_t>(it - names.begin()), shape, ppc, velocity);
  });
  if (added == 0) node.fail("the region contains no material point (too small for the grid?)");
}

Obstacle read_obstacle(const JsonNode& node, bool friction) {
  node.allow_only({"line", "polygon", "k_n", "k_t", "friction", "damping", "velocity", "remove_at", "release"});
  if (node.has("line") == node.has("polygon")) node.fail("an obstacle needs exactly one of \"line\" and \"polygon\"");
  if (!friction && (node.has("friction") || node.has("k_t")))
    node.fail("\"friction\" and \"k_t\" need effects.boundary_friction");
  const bool closed = node.has("polygon");
  Polyline shape{vertices(*node.find(closed ? "polygon" : "line")), closed};
  ContactParameters c;
  c.k_n = node.number("k_n", Range::positive());
  c.k_t = friction ? node.number("k_t", Range::at_least(0)) : 0;
  c.friction = friction ? node.number("friction", Range::at_least(0)) : 0;
  c.damping_ratio = node.number_or("damping", 0.5, Range::between(0, 1, false, false));
  const Vec2 velocity = node.has("velocity") ? vec2(node.at("velocity", "")) : Vec2::Zero();
  if (node.has("remove_at") && node.has("release"))
    node.fail("give either \"remove_at\" (a sudden removal) or \"release\" (letting go over an interval), not both");
  ObstacleRelease release = ObstacleRelease::at(node.number_or("remove_at", kInfinity, Range::at_least(0)));
  if (const auto r = node.find("release")) {
    r->allow_only({"start", "end"});
    release = {r->number("start", Range::at_least(0)), r->number("end", Range::at_least(0))};
    if (!(release.end > release.start)) r->fail("expected end > start (a sudden removal is \"remove_at\")");
  }
  return common::at_node(node, [&] { return Obstacle(std::move(shape), c, velocity, release); });
}

Gravity read_gravity(const JsonNode& node) {
  node.allow_only({"g", "ramp"});
  Gravity g{vec2(node.at("g", "[g_x, g_y]")), std::nullopt};
  if (const auto r = node.find("ramp")) {
    r->allow_only({"from", "start", "end"});
    GravityRamp ramp{r->has("from") ? vec2(r->at("from", "")) : Vec2::Zero(), r->number("start", Range::at_least(0)),
                     r->number("end", Range::at_least(0))};
    if (!(ramp.end > ramp.start)) r->fail("expected end > start");
    g.ramp = ramp;
  }
  return g;
}

}  // namespace

Scene load_scene(const std::filesystem::path& file, int rank, int ranks) {
  const nlohmann::json doc = common::load_json_file(file);
  const JsonNode root(doc, file.filename().string());
  root.require_object();
  root.allow_only({"grid", "time", "integration", "regularization", "effects", "gravity", "channel_walls", "materials",
                   "regions", "obstacles", "tracked_points", "audit"});
  const std::filesystem::path folder = file.parent_path();

  Scene scene;
  const JsonNode time = root.at("time", "an object with end and output_interval");
  time.allow_only({"end", "output_interval", "series_interval", "max_time_step", "min_time_step", "cfl",
                   "contact_factor", "stop_at_rest", "stop_at_front"});
  scene.end_time = time.number("end", Range::positive());
  if (const auto rest = time.find("stop_at_rest")) {
    rest->allow_only({"kinetic_energy_fraction", "not_before"});
    scene.stop_at_rest = RestCriterion{rest->number("kinetic_energy_fraction", Range::between(0, 1, false, false)),
                                       rest->number_or("not_before", 0.0, Range::at_least(0))};
  }
  if (const auto front = time.find("stop_at_front")) {
    front->allow_only({"x", "not_before"});
    scene.stop_at_front = FrontCriterion{front->number("x", Range::any()),
                                         front->number_or("not_before", 0.0, Range::at_least(0))};
  }
  scene.output_interval = time.number("output_interval", Range::positive());
  scene.series_interval = time.number_or("series_interval", scene.output_interval, Range::positive());

  SolverSettings settings;
  settings.max_time_step = time.number_or("max_time_step", kInfinity, Range::positive());
  scene.min_time_step = time.number_or("min_time_step", 0.0, Range::between(0, settings.max_time_step, true, true));
  settings.time_step.cfl = time.number_or("cfl", settings.time_step.cfl, Range::between(0, 1, true, false));
  settings.time_step.contact = time.number_or("contact_factor", settings.time_step.contact, Range::between(0, 1, true, false));
  if (const auto integration = root.find("integration")) {
    // The old per-step blend has no Δt-independent meaning: name its replacement instead of refusing it
    // as an unknown key.
    if (const auto flip = integration->find("flip"))
      flip->fail("the per-step blend \"flip\" was replaced by \"transfer\": {\"apic_flip\": {\"pic_rate\": 5}} (the "
                 "default) or {\"flip_pic\": {\"pic_rate\": r}}, r the PIC fraction per second (flip f at steps of dt: "
                 "r = -ln(f) / dt)");
    integration->allow_only(
        {"transfer", "sort_interval", "skip_strain_increment", "homogeneous_drive", "rebalance_interval"});
    if (const auto transfer = integration->find("transfer")) settings.transfer = read_transfer(*transfer);
    if (const auto drive = integration->find("homogeneous_drive")) settings.homogeneous_drive = read_homogeneous_drive(*drive);
    settings.skip_strain_increment =
        integration->number_or("skip_strain_increment", settings.skip_strain_increment, Range::at_least(0));
    settings.sort_interval = static_cast<int>(integration->integer_or("sort_interval", settings.sort_interval, 1, 1000000));
    settings.rebalance_interval =
        static_cast<int>(integration->integer_or("rebalance_interval", settings.rebalance_interval, 1, 1000000000));
  }
  if (const auto regularization = root.find("regularization")) {
    regularization->allow_only({"nonlocal_length"});
    settings.regularization.emplace(regularization->number("nonlocal_length", Range::positive()));
  }
  const auto effects = root.find("effects");
  const bool channel_walls = effects && effects->boolean_or("channel_walls", false);
  if (channel_walls != root.has("channel_walls"))
    root.fail(channel_walls ? "effects.channel_walls is on but there is no \"channel_walls\" block"
                            : "a \"channel_walls\" block needs effects.channel_walls");
  if (channel_walls) {
    const JsonNode walls = root.at("channel_walls", "an object with width and friction");
    walls.allow_only({"width", "friction"});
    settings.channel_walls.emplace(walls.number("width", Range::positive()), walls.number("friction", Range::at_least(0)));
  }
  const JsonNode grid = root.at("grid", "an object with cell_size and cells");
  scene.solver = std::make_unique<Solver>(common::at_node(grid, [&] { return read_grid(grid); }), settings);

  bool gravity = false, boundary_friction = false;
  LawContext law_context{folder, {}, rank, ranks};
  DemEffects& dem_effects = law_context.effects;
  if (effects) {
    effects->allow_only({"gravity", "boundary_friction", "channel_walls", "cohesion", "kinetic_stress",
                         "rolling_resistance"});
    gravity = effects->boolean_or("gravity", false);
    boundary_friction = effects->boolean_or("boundary_friction", false);
    for (auto [name, flag] : {std::pair{"cohesion", &dem_effects.cohesion}, std::pair{"kinetic_stress", &dem_effects.kinetic_stress},
                              std::pair{"rolling_resistance", &dem_effects.rolling_resistance}})
      if (effects->has(name)) *flag = effects->boolean_or(name, false);
  }
  if (gravity != root.has("gravity"))
    root.fail(gravity ? "effects.gravity is on but there is no \"gravity\" block"
                      : "a \"gravity\" block needs effects.gravity");
  if (gravity) scene.solver->set_gravity(read_gravity(root.at("gravity", "")));

  const JsonNode materials = root.at("materials", "a non-empty array of materials");
  const std::size_t n_materials = materials.array_size("a non-empty array of materials");
  if (n_materials == 0) materials.fail_expected("a non-empty array of materials");
  for (std::size_t k = 0; k < n_materials; ++k) {
    const JsonNode m = materials.at(k);
    const std::string name = m.at("name", "a material name (string)").string();
    if (std::find(scene.material_names.begin(), scene.material_names.end(), name) != scene.material_names.end())
      m.at("name", "").fail("duplicate material name");
    scene.solver->add_law(read_law(m, law_context));
    scene.material_names.push_back(name);
  }
  const JsonNode regions = root.at("regions", "a non-empty array of regions");
  const std::size_t n_regions = regions.array_size("a non-empty array of regions");
  if (n_regions == 0) regions.fail_expected("a non-empty array of regions");
  for (std::size_t k = 0; k < n_regions; ++k) read_region(regions.at(k), *scene.solver, scene.material_names);

  if (const auto obstacles = root.find("obstacles"))
    for (std::size_t k = 0, n = obstacles->array_size("an array of obstacles"); k < n; ++k)
      scene.solver->add_obstacle(read_obstacle(obstacles->at(k), boundary_friction));

  if (const auto tracked = root.find("tracked_points"))
    for (std::size_t k = 0, n = tracked->array_size("an array of [x, y] positions"); k < n; ++k) {
      // The material point nearest to the given position at t = 0.
      const Vec2 x = vec2(tracked->at(k));
      const auto& points = scene.solver->points();
      const auto nearest = std::min_element(points.begin(), points.end(), [&](const auto& a, const auto& b) {
        return (a.position - x).squaredNorm() < (b.position - x).squaredNorm();
      });
      scene.tracked_points.push_back(nearest->id);
    }
  if (const auto audit = root.find("audit")) {
    audit->allow_only({"points"});
    const JsonNode points = audit->at("points", "the number of points whose history the run records (integer >= 1)");
    const auto count = static_cast<std::size_t>(points.integer(1));
    scene.audited_points = common::at_node(points, [&] { return spread_audit_points(*scene.solver, count); });
  }
  return scene;
}

}  // namespace grainbank::mpm::io
