#include "seqtopo/simulator/scenarios.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "decorate.hpp"
#include "seqtopo/simulator/random.hpp"

namespace seqtopo::simulator {
namespace {

using detail::decorate;
using detail::DecorStyle;

constexpr double kCell = 0.25;          // [m] grid resolution of every scenario
constexpr double kCorridorWidth = 2.2;  // [m]

const std::vector<Colour>& wall_paints() {
  static const std::vector<Colour> paints{rgb(226, 216, 190), rgb(205, 210, 214), rgb(196, 220, 196),
                                          rgb(190, 208, 228), rgb(232, 222, 160), rgb(228, 196, 180),
                                          rgb(215, 205, 230), rgb(240, 240, 236)};
  return paints;
}

int paint(GridWorld& w, Colour c) {
  return w.add_material({Pattern::plain, c, {c[0] * 0.55F, c[1] * 0.55F, c[2] * 0.55F}, 2.6, 1.0});
}

// Office floors and walls shared by the indoor scenarios.
struct Office {
  int carpet, lino, tiles;
  std::vector<int> walls;  // paint materials
  int panels, brick;
};

Office office_materials(GridWorld& w) {
  Office o{};
  o.carpet = w.add_ground({Pattern::tiles, rgb(112, 118, 130), rgb(98, 104, 116), 0.5, true});
  o.lino = w.add_ground({Pattern::tiles, rgb(176, 168, 150), rgb(140, 132, 118), 0.3, true});
  o.tiles = w.add_ground({Pattern::tiles, rgb(200, 200, 196), rgb(150, 150, 150), 0.4, true});
  for (const Colour& c : wall_paints()) o.walls.push_back(paint(w, c));
  o.panels = w.add_material({Pattern::panels, rgb(170, 120, 75), rgb(90, 60, 35), 2.6, 0.6});
  o.brick = w.add_material({Pattern::brick, rgb(165, 80, 55), rgb(200, 195, 185), 2.6, 1.0});
  return o;
}

// The first traversal is lit normally; later ones get gain 0.8-1.15 and a +-5 % tint, scaled by `change`.
Lighting traversal_lighting(Rng& rng, int leg, double noise, double change) {
  Lighting l;
  l.noise_sigma = noise;
  if (leg == 0) return l;
  l.gain = 1.0 + change * (rng.uniform(0.8, 1.15) - 1.0);
  for (double& t : l.tint) t = 1.0 + change * rng.uniform(-0.05, 0.05);
  return l;
}

OdometryNoise indoor_odometry() { return {0.01, 0.003, 0.01, 0.01}; }
OdometryNoise outdoor_odometry() { return {0.02, 0.002, 0.02, 0.01}; }

void set_legs(ScenarioSetup& s, std::vector<std::vector<int>> node_lists, Rng& rng, const SimulationConfig& config,
              std::vector<PathFollowing> following = {}) {
  for (std::size_t k = 0; k < node_lists.size(); ++k) {
    RouteLeg leg;
    leg.nodes = std::move(node_lists[k]);
    if (k < following.size()) leg.following = following[k];
    leg.lighting = traversal_lighting(rng, static_cast<int>(k), config.pixel_noise, config.lighting_change);
    s.legs.push_back(std::move(leg));
  }
}

// Carves every edge of the graph as a corridor.
void carve_graph(GridWorld& w, const PathGraph& g, double width, int ground) {
  for (const auto& [a, b] : g.edges) {
    w.carve_corridor(g.nodes[static_cast<std::size_t>(a)], g.nodes[static_cast<std::size_t>(b)], width, ground);
  }
}

// ---------------------------------------------------------------- figure-eight (mapping paper Fig. 1)
ScenarioSetup figure_eight(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "figure-eight";
  s.interval = 0.25;
  s.odometry = indoor_odometry();
  Rng rng(config.seed, 1);
  GridWorld w({-4, -10, 36, 19}, kCell);
  const Office o = office_materials(w);
  w.fill(w.bounds(), o.walls[0]);
  w.fill({-4, 4, 36, 19}, o.walls[3]);      // north wing in another colour
  w.fill({24, -10, 36, 4}, o.walls[4]);     // east exit
  w.fill({9.5, 1.5, 20.5, 8.5}, o.panels);  // meeting room inside the loop
  PathGraph& g = s.graph;
  const int start = g.add_node({0, 0}), j1 = g.add_node({8, 0}), j2 = g.add_node({22, 0}), n1 = g.add_node({22, 10}),
            n2 = g.add_node({8, 10}), end = g.add_node({32, 0}), side = g.add_node({1, 10}), up = g.add_node({22, 16});
  g.add_edge(start, j1);
  g.add_edge(j1, j2);
  g.add_edge(j2, n1);
  g.add_edge(n1, n2);
  g.add_edge(n2, j1);
  g.add_edge(j2, end);
  g.add_edge(n2, side);  // corridors the route never takes
  g.add_edge(n1, up);
  carve_graph(w, g, kCorridorWidth, o.carpet);
  w.carve({11, 2.5, 19, 7.5}, o.lino);  // meeting room, open to both corridors
  w.carve({12.5, 1.0, 14.0, 2.6}, o.lino);
  w.carve({16.0, 7.4, 17.5, 9.0}, o.lino);
  w.carve({11, -8, 19, -3}, o.tiles);  // kitchen south of the shared corridor
  w.carve({14, -3.2, 16, -1.0}, o.tiles);
  Rng decor(config.seed, 2);
  decorate(w, w.bounds(), detail::office_style(), decor);
  s.world = std::move(w);
  // The second pass drives a little left of the first: never exactly the same line twice.
  set_legs(s, {{start, j1, j2, n1, n2, j1}, {j1, j2, end}}, rng, config, {{}, {0.25, 0, 4}});
  return s;
}

// ---------------------------------------------------------------- corridor-reverse (experiment 1)
ScenarioSetup corridor_reverse(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "corridor-reverse";
  s.interval = 0.25;
  s.odometry = indoor_odometry();
  Rng rng(config.seed, 1);
  GridWorld w({-3, -9, 48, 14}, kCell);
  const Office o = office_materials(w);
  w.fill(w.bounds(), o.walls[1]);
  w.fill({-3, -9, 12, 14}, o.walls[0]);
  w.fill({24, -9, 48, 14}, o.walls[5]);
  const int stair_tiles = w.add_material({Pattern::tiles, rgb(236, 236, 232), rgb(170, 170, 170), 2.6, 0.3});
  const int stair_rail = w.add_material({Pattern::glass, rgb(150, 175, 180), rgb(70, 70, 75), 2.6, 0.9});
  const int steps = w.add_material({Pattern::stripes, rgb(90, 90, 95), rgb(200, 200, 200), 2.6, 0.3});
  PathGraph& g = s.graph;
  const int a = g.add_node({0, 0}), b = g.add_node({34, 0}), c = g.add_node({44, 0}), d = g.add_node({44, 10}),
            e = g.add_node({34, 10});
  g.add_edge(a, b);
  g.add_edge(b, c);
  g.add_edge(c, d);
  g.add_edge(d, e);
  g.add_edge(e, b);
  carve_graph(w, g, kCorridorWidth, o.carpet);
  // Offices off the corridor, some open: views into them make each stretch distinct.
  const double offices[][4] = {{4, 1.5, 10, 7}, {13, -7, 19, -1.5}, {21, 1.5, 27, 7}, {27, -7, 32, -1.5}};
  for (const auto& r : offices) w.carve({r[0], r[1], r[2], r[3]}, o.lino);
  w.carve({6, 1.0, 7.5, 1.6}, o.lino);
  w.carve({15, -1.6, 16.5, -1.0}, o.lino);
  w.carve({24.5, 1.0, 26.0, 1.6}, o.lino);
  // The stair well the robot loops around.
  w.fill({35.5, 1.5, 42.5, 8.5}, stair_tiles);
  w.fill({36.5, 2.5, 41.5, 7.5}, steps);
  w.fill({35.5, 4.0, 35.8, 6.0}, stair_rail);
  decorate(w, w.bounds(), detail::office_style(), rng);
  s.world = std::move(w);
  Rng legs_rng(config.seed, 3);
  // Both ways along the corridor's centre line, as the paper's robot was driven. (Keeping 0.15 m right
  // each way, 0.3 m apart, already hides the reverse revisit from the joint-histogram similarity.)
  set_legs(s, {{a, b, c, d, e, b}, {b, a}}, legs_rng, config);
  return s;
}

// ---------------------------------------------------------------- campus: nested loops, zig-zag
// Three loops side by side (x = 0, 22, 45, 70; y = 0, 35), outdoors except the top half of the right loop,
// which runs through a building's corridor (mapping paper Fig. 5).
struct Campus {
  int n[4][2];
};

Campus build_campus(ScenarioSetup& s, const SimulationConfig& config) {
  GridWorld w({-14, -14, 84, 49}, kCell);
  w.add_ground({Pattern::foliage, rgb(70, 130, 50), rgb(110, 150, 60), 0.5, false});  // grass: the default ground
  const int paving = w.add_ground({Pattern::concrete, rgb(165, 160, 150), rgb(120, 116, 110), 0.6, false});
  const int asphalt = w.add_ground({Pattern::concrete, rgb(85, 85, 90), rgb(60, 60, 64), 3.0, false});
  const Office o = office_materials(w);
  w.ceiling_height = 2.7;
  const int red_brick = w.add_material({Pattern::brick, rgb(160, 75, 50), rgb(205, 200, 190), 9.0, 1.0});
  const int yellow_brick = w.add_material({Pattern::brick, rgb(200, 170, 110), rgb(230, 225, 215), 7.0, 1.0});
  const int concrete = w.add_material({Pattern::concrete, rgb(175, 172, 165), rgb(120, 118, 112), 14.0, 1.5});
  const int glass = w.add_material({Pattern::glass, rgb(90, 130, 170), rgb(50, 55, 60), 11.0, 1.5});
  const int far_block = w.add_material({Pattern::concrete, rgb(150, 155, 165), rgb(110, 112, 120), 18.0, 3.0});
  const int tree = w.add_material({Pattern::tree, rgb(50, 110, 40), rgb(95, 70, 45), 6.0, 1.0});
  const int hedge = w.add_material({Pattern::foliage, rgb(40, 95, 35), rgb(80, 120, 40), 1.1, 1.0});
  const int lamp = w.add_material({Pattern::plain, rgb(55, 58, 60), rgb(40, 40, 40), 4.5, 1.0});
  const int interior = paint(w, wall_paints()[6]);

  Campus c{};
  PathGraph& g = s.graph;
  const double xs[4] = {0, 22, 45, 70}, ys[2] = {0, 35};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 2; ++j) c.n[i][j] = g.add_node({xs[i], ys[j]});
  }
  for (int i = 0; i < 3; ++i) {
    g.add_edge(c.n[i][0], c.n[i + 1][0]);
    g.add_edge(c.n[i][1], c.n[i + 1][1]);
  }
  for (int i = 0; i < 4; ++i) g.add_edge(c.n[i][0], c.n[i][1]);

  // Skyline: tall blocks all round, varied so directions can be told apart.
  Rng rng(config.seed, 11);
  for (double x = -14; x < 84; x += 9) {
    w.fill({x, -14, x + rng.uniform(5, 8.5), -11.5}, rng.chance(0.5) ? far_block : red_brick);
    w.fill({x, 46.5, x + rng.uniform(5, 8.5), 49}, rng.chance(0.5) ? far_block : concrete);
  }
  for (double y = -14; y < 49; y += 10) {
    w.fill({-14, y, -11.5, y + rng.uniform(5, 9)}, rng.chance(0.5) ? far_block : yellow_brick);
    w.fill({81.5, y, 84, y + rng.uniform(5, 9)}, rng.chance(0.5) ? concrete : far_block);
  }
  // Buildings inside the loops.
  w.fill({4, 4, 18, 31}, red_brick);
  w.fill({27, 4, 40, 20}, concrete);
  w.fill({27, 23, 40, 31}, glass);
  w.carve({40, 20, 43, 23}, paving);
  // The indoor building over the top half of the right loop: brick shell, painted inside.
  w.fill({42.5, 17, 72.5, 38}, red_brick);
  w.fill({43.0, 17.5, 72.0, 37.5}, interior);
  w.fill({49, 20, 66, 32}, o.walls[2]);
  carve_graph(w, g, 3.0, paving);
  for (int i : {2, 3}) w.carve_corridor({xs[i], 17}, {xs[i], 35}, kCorridorWidth, o.lino);
  w.carve_corridor({45, 35}, {70, 35}, kCorridorWidth, o.lino);
  w.carve({50, 31, 56, 33.9}, o.carpet);  // an open-plan office off the corridor
  // Car park below the indoor corridor, with a hedge.
  w.carve({48, 3, 67, 14}, asphalt);
  w.fill({48, 14, 60, 14.5}, hedge);
  w.fill({-8, 37, 14, 37.5}, hedge);
  // Trees and lamp posts beside the paths.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 2; ++j) {
      const double y = ys[j] + (j == 0 ? -2.6 : 2.6);
      if (j == 1 && i == 2) continue;  // indoors
      for (double x = xs[i] + 3; x < xs[i + 1] - 2; x += rng.uniform(4.5, 8)) {
        if (rng.chance(0.7))
          w.fill({x, y - 0.5, x + 0.5, y}, tree);
        else
          w.fill({x, y - 0.25, x + 0.25, y}, lamp);
      }
    }
  }
  for (int i = 0; i < 4; ++i) {
    const double x = xs[i] + (i == 3 ? 2.6 : -2.6);
    const double top = i >= 2 ? 16 : 33;
    for (double y = 3; y < top; y += rng.uniform(5, 9)) {
      if (rng.chance(0.6))
        w.fill({x - 0.5, y, x, y + 0.5}, tree);
      else
        w.fill({x, y, x + 0.25, y + 0.25}, lamp);
    }
  }
  Rng decor(config.seed, 12);
  decorate(w, {-14, -14, 84, 17}, detail::facade_style(), decor);
  decorate(w, {-14, 38, 84, 49}, detail::facade_style(), decor);
  decorate(w, {-14, 17, 42.4, 38}, detail::facade_style(), decor);
  decorate(w, {42.6, 17.1, 72.4, 37.9}, detail::office_style(), decor);
  s.world = std::move(w);
  return c;
}

ScenarioSetup nested_loops(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "nested-loops";
  s.interval = 0.5;
  s.odometry = outdoor_odometry();
  const Campus c = build_campus(s, config);
  Rng rng(config.seed, 1);
  const auto& n = c.n;
  set_legs(s,
           {{n[0][0], n[1][0], n[1][1], n[0][1], n[0][0]},
            {n[0][0], n[1][0], n[2][0], n[2][1], n[1][1], n[1][0]},
            {n[1][0], n[2][0], n[3][0], n[3][1], n[2][1], n[2][0]}},
           rng, config, {{}, {0.3, 0, 4}, {-0.3, 0, 4}});
  return s;
}

ScenarioSetup zigzag(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "zigzag";
  s.interval = 0.5;
  s.odometry = outdoor_odometry();
  const Campus c = build_campus(s, config);
  Rng rng(config.seed, 1);
  const auto& n = c.n;
  PathFollowing zig;
  zig.zigzag_amplitude = config.zigzag_amplitude.value_or(0.6);
  zig.zigzag_period = 3.0;
  set_legs(s,
           {{n[0][0], n[1][0], n[1][1], n[0][1], n[0][0]},
            {n[0][0], n[1][0], n[2][0], n[2][1], n[1][1], n[1][0]},
            {n[1][0], n[2][0], n[2][1], n[1][1], n[0][1], n[0][0], n[1][0]}},
           rng, config, {{}, {}, zig});
  return s;
}

// ---------------------------------------------------------------- aliasing
// Three identical 30 m corridors joined into a serpentine. The middle one is walked westwards, so it is
// decorated as the others turned through 180 degrees: every corridor looks the same in the direction of
// travel, yet none is a revisit.
ScenarioSetup aliasing(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "aliasing";
  s.interval = 0.25;
  s.odometry = indoor_odometry();
  GridWorld w({-3, -4, 33, 16}, kCell);
  const Office o = office_materials(w);
  w.fill(w.bounds(), o.walls[0]);
  PathGraph& g = s.graph;
  const double length = 30, gap = 6;
  int nodes[3][2];
  for (int k = 0; k < 3; ++k) {
    nodes[k][0] = g.add_node({k % 2 == 0 ? 0.0 : length, k * gap});
    nodes[k][1] = g.add_node({k % 2 == 0 ? length : 0.0, k * gap});
    g.add_edge(nodes[k][0], nodes[k][1]);
    if (k > 0) g.add_edge(nodes[k - 1][1], nodes[k][0]);
  }
  carve_graph(w, g, kCorridorWidth, o.carpet);
  // One decoration list for the left and right walls, in metres from the corridor's start.
  Rng rng(config.seed, 21);
  const DecorStyle style = detail::office_style();
  struct Item {
    bool left;
    double at;
    int kind;
    std::uint64_t seed;
  };
  std::vector<Item> items;
  for (int wall = 0; wall < 2; ++wall) {
    for (double at = rng.uniform(1.5, 3); at < length - 3; at += rng.uniform(2.0, 4.5)) {
      const int kinds[] = {0, 0, 1, 2, 3, 5};
      items.push_back({wall == 0, at, kinds[rng.below(6)], rng.next()});
    }
  }
  const double half = kCorridorWidth / 2;
  for (int k = 0; k < 3; ++k) {
    const bool east = k % 2 == 0;
    const double y = k * gap;
    for (const Item& it : items) {
      // Travelling east the left wall is the north one; travelling west, the south one.
      const bool north = it.left == east;
      detail::FaceRun run{north ? Side::south : Side::north, north ? y + half : y - half, 0, length};
      Rng item_rng(it.seed);
      // Place with a probe first to learn the width, then mirror the position for westward corridors.
      GridWorld probe({0, 0, 1, 1}, 1.0);
      Rng probe_rng(it.seed);
      const double width = detail::place_item(probe, {Side::north, 0.5, 0, 1}, 0, it.kind, style, probe_rng, 10.0);
      const double u = east ? it.at : length - it.at - width;
      detail::place_item(w, run, u, it.kind, style, item_rng, 10.0);
    }
  }
  s.world = std::move(w);
  Rng legs_rng(config.seed, 22);
  set_legs(s, {{nodes[0][0], nodes[0][1], nodes[1][0], nodes[1][1], nodes[2][0], nodes[2][1]}}, legs_rng, config);
  return s;
}

// ---------------------------------------------------------------- localization surveys
Lighting survey_lighting(Rng& rng, bool map, double noise, double change) {
  Lighting l;
  l.noise_sigma = noise;
  if (map) return l;
  l.gain = 1.0 + change * (rng.uniform(0.85, 1.12) - 1.0);
  for (double& t : l.tint) t = 1.0 + change * rng.uniform(-0.04, 0.04);
  return l;
}

double survey_heading(Rng& rng) { return rng.normal() * 2.0 * std::numbers::pi / 180.0; }

void add_point(ScenarioSetup& s, Rng& rng, const std::string& id, bool map, Vec2 p, const SimulationConfig& config) {
  s.points.push_back({id, map, {p.x, p.y, survey_heading(rng)}, 0});
  s.point_lighting.push_back(survey_lighting(rng, map, config.pixel_noise, config.lighting_change));
}

std::string numbered(char prefix, int k) {
  std::string id(1, prefix);
  if (k < 10) id += '0';
  return id + std::to_string(k);
}

// Each test point's place is its nearest map point (the geometric ground truth).
void assign_places(ScenarioSetup& s) {
  std::vector<int> map_index;
  for (std::size_t k = 0; k < s.points.size(); ++k) {
    if (s.points[k].map) {
      s.points[k].place = static_cast<int>(map_index.size());
      map_index.push_back(static_cast<int>(k));
    }
  }
  for (auto& p : s.points) {
    if (p.map) continue;
    double best = 1e18;
    for (int m : map_index) {
      const auto& q = s.points[static_cast<std::size_t>(m)];
      const double d = std::hypot(p.pose.x - q.pose.x, p.pose.y - q.pose.y);
      if (d < best) {
        best = d;
        p.place = q.place;
      }
    }
  }
}

ScenarioSetup rooms(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "rooms";
  s.kind = ScenarioKind::survey;
  GridWorld w({0, 0, 42, 17}, kCell);
  const Office o = office_materials(w);
  w.fill(w.bounds(), o.walls[1]);
  Rng rng(config.seed, 31);
  const std::vector<int> grounds{o.carpet, o.lino, o.tiles,
                                 w.add_ground({Pattern::tiles, rgb(150, 105, 70), rgb(120, 80, 50), 0.15, true}),
                                 w.add_ground({Pattern::tiles, rgb(90, 120, 95), rgb(70, 95, 75), 0.5, true})};
  std::vector<int> wall_materials = o.walls;
  wall_materials.push_back(o.panels);
  wall_materials.push_back(o.brick);
  const int cabinet = w.add_material({Pattern::panels, rgb(120, 120, 125), rgb(80, 80, 85), 1.9, 0.45});
  const int desk = w.add_material({Pattern::plain, rgb(180, 150, 110), rgb(140, 110, 80), 0.75, 1.0});
  const int shelf = w.add_material({Pattern::stripes, rgb(140, 90, 50), rgb(60, 80, 150), 2.0, 0.12});
  int map_count = 0, test_count = 0;
  for (int room = 0; room < 10; ++room) {
    const double cx = 4.2 + 8.2 * (room % 5), cy = 4.2 + 8.4 * (room / 5);
    const double hw = rng.uniform(2.3, 3.4), hh = rng.uniform(2.0, 3.2);
    const Rect r{cx - hw, cy - hh, cx + hw, cy + hh};
    // Each wall of the room (a 0.5 m shell) in its own material.
    const Rect walls[4] = {{r.x0 - 0.5, r.y0, r.x0, r.y1},
                           {r.x1, r.y0, r.x1 + 0.5, r.y1},
                           {r.x0 - 0.5, r.y0 - 0.5, r.x1 + 0.5, r.y0},
                           {r.x0 - 0.5, r.y1, r.x1 + 0.5, r.y1 + 0.5}};
    for (const Rect& wr : walls)
      w.fill(wr, wall_materials[static_cast<std::size_t>(rng.below(static_cast<int>(wall_materials.size())))]);
    w.carve(r, grounds[static_cast<std::size_t>(rng.below(static_cast<int>(grounds.size())))]);
    // Furniture against the walls.
    const int pieces = 1 + rng.below(3);
    for (int f = 0; f < pieces; ++f) {
      const int m = f == 0 ? cabinet : (rng.chance(0.5) ? desk : shelf);
      const double len = rng.uniform(0.8, 1.8), depth = m == desk ? 0.75 : 0.5;
      switch (rng.below(4)) {
        case 0: {
          const double x = rng.uniform(r.x0, r.x1 - len);
          w.fill({x, r.y0, x + len, r.y0 + depth}, m);
          break;
        }
        case 1: {
          const double x = rng.uniform(r.x0, r.x1 - len);
          w.fill({x, r.y1 - depth, x + len, r.y1}, m);
          break;
        }
        case 2: {
          const double y = rng.uniform(r.y0, r.y1 - len);
          w.fill({r.x0, y, r.x0 + depth, y + len}, m);
          break;
        }
        default: {
          const double y = rng.uniform(r.y0, r.y1 - len);
          w.fill({r.x1 - depth, y, r.x1, y + len}, m);
          break;
        }
      }
    }
    if (rng.chance(0.4)) {  // a pillar
      const double px = cx + (rng.chance(0.5) ? -1 : 1) * hw * 0.55, py = cy + (rng.chance(0.5) ? -1 : 1) * hh * 0.55;
      w.fill({px - 0.25, py - 0.25, px + 0.25, py + 0.25}, o.walls[7]);
    }
    DecorStyle style = detail::office_style();
    style.spacing = 1.0;
    style.windows = 0;
    decorate(w, r, style, rng);
    add_point(s, rng, numbered('m', map_count++), true, {cx + rng.uniform(-0.1, 0.1), cy + rng.uniform(-0.1, 0.1)},
              config);
    const int map_index = static_cast<int>(s.points.size()) - 1;
    for (int t = 0; t < 3; ++t) {
      const double a = rng.uniform(0, 2 * std::numbers::pi), d = rng.uniform(0.3, 0.6);
      add_point(s, rng, numbered('t', test_count++), false, {cx + d * std::cos(a), cy + d * std::sin(a)}, config);
      s.adjacency.push_back({static_cast<int>(s.points.size()) - 1, map_index});
    }
  }
  s.world = std::move(w);
  assign_places(s);
  return s;
}

// A test point between map points a and b, at fraction f, shifted sideways by `side` [m].
Vec2 between(Vec2 a, Vec2 b, double f, double side) {
  const Vec2 d = b - a;
  const double len = norm(d);
  const Vec2 n{-d.y / len, d.x / len};
  return a + f * d + side * n;
}

ScenarioSetup ground_floor(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "ground-floor";
  s.kind = ScenarioKind::survey;
  GridWorld w({-9, -9, 40, 27}, kCell);
  const Office o = office_materials(w);
  w.fill(w.bounds(), o.walls[0]);
  w.fill({12, -9, 40, 27}, o.walls[2]);
  w.fill({26, 8, 40, 27}, o.walls[3]);
  const int glass = w.add_material({Pattern::glass, rgb(120, 160, 190), rgb(60, 60, 65), 2.6, 1.2});
  Rng rng(config.seed, 41);
  // Entry hall with a glass front, the corridor east, the corridor north, the conference room.
  w.carve({-6, -5, 3, 5}, o.tiles);
  w.fill({-6.5, -3, -6, 3}, glass);
  w.carve_corridor({0, 0}, {30, 0}, kCorridorWidth, o.lino);
  w.carve_corridor({30, 0}, {30, 15}, kCorridorWidth, o.carpet);
  w.carve({25, 15, 36, 24}, o.carpet);
  w.fill({31.5, 18.5, 34.5, 21.5}, w.add_material({Pattern::plain, rgb(160, 110, 70), rgb(120, 80, 50), 0.75, 1.0}));
  w.fill({36, 17, 36.5, 22}, glass);
  // Offices and a lobby off the corridors.
  w.carve({8, 1.5, 13, 6}, o.carpet);
  w.carve({9.5, 1.0, 11, 1.6}, o.carpet);
  w.carve({17, -6, 23, -1.5}, o.tiles);
  w.carve({19, -1.6, 20.5, -1.0}, o.tiles);
  w.carve({31.5, 6, 36, 10}, o.lino);
  w.carve({31.0, 7, 31.6, 8.5}, o.lino);
  decorate(w, w.bounds(), detail::office_style(), rng);
  // 21 map points evenly along the way (-4, 0) -> (30, 0) -> (30, 19).
  const double total = 34 + 19;
  std::vector<Vec2> map_points;
  for (int k = 0; k < 21; ++k) {
    const double at = total * k / 20.0;
    const Vec2 p = at <= 34 ? Vec2{-4 + at, 0} : Vec2{30, at - 34};
    map_points.push_back(p + Vec2{rng.uniform(-0.15, 0.15), rng.uniform(-0.15, 0.15)});
  }
  for (int k = 0; k < 21; ++k)
    add_point(s, rng, numbered('m', k), true, map_points[static_cast<std::size_t>(k)], config);
  // 22 test points: one in each of the 20 gaps, a second in two of them.
  int test = 0;
  for (int gap = 0; gap < 20; ++gap) {
    const int count = (gap == 5 || gap == 14) ? 2 : 1;
    for (int c = 0; c < count; ++c) {
      const double f = count == 1 ? rng.uniform(0.3, 0.7) : (c == 0 ? rng.uniform(0.2, 0.4) : rng.uniform(0.6, 0.8));
      const Vec2 p = between(map_points[static_cast<std::size_t>(gap)], map_points[static_cast<std::size_t>(gap + 1)],
                             f, rng.uniform(-0.4, 0.4));
      add_point(s, rng, numbered('t', test++), false, p, config);
      const int t = static_cast<int>(s.points.size()) - 1;
      s.adjacency.push_back({t, gap});
      s.adjacency.push_back({t, gap + 1});
    }
  }
  s.world = std::move(w);
  assign_places(s);
  return s;
}

ScenarioSetup white_hall(const SimulationConfig& config) {
  ScenarioSetup s;
  s.name = "white-hall";
  s.kind = ScenarioKind::survey;
  GridWorld w({-2, -2, 22, 15}, kCell);
  w.ceiling_height = 4.0;
  const int white = w.add_material({Pattern::plain, rgb(242, 242, 238), rgb(200, 200, 196), 4.0, 1.0});
  const int column = w.add_material({Pattern::plain, rgb(250, 250, 248), rgb(215, 215, 210), 4.0, 1.0});
  const int glass = w.add_material({Pattern::glass, rgb(170, 195, 215), rgb(225, 225, 225), 4.0, 1.8});
  const int stairs = w.add_material({Pattern::stripes, rgb(230, 230, 226), rgb(170, 170, 168), 4.0, 0.3});
  const int desk = w.add_material({Pattern::panels, rgb(235, 235, 230), rgb(180, 180, 176), 1.1, 0.8});
  const int marble = w.add_ground({Pattern::tiles, rgb(225, 222, 215), rgb(195, 192, 186), 0.8, true});
  w.fill(w.bounds(), white);
  w.carve({0, 0, 20, 13}, marble);
  w.fill({6, -0.5, 14, 0}, glass);    // entrance
  w.fill({20, 3, 20.5, 10}, stairs);  // stair case to the east
  w.fill({7, 11.8, 13, 12.6}, desk);  // reception desk
  for (const Vec2 c : {Vec2{4.75, 6.5}, Vec2{8.25, 6.5}, Vec2{11.75, 6.5}, Vec2{15.25, 6.5}}) {  // a colonnade
    w.fill({c.x - 0.3, c.y - 0.3, c.x + 0.3, c.y + 0.3}, column);
  }
  // Few features: white doors, a painting, a notice board, a fire hose box.
  Rng rng(config.seed, 51);
  DecorStyle style = detail::office_style();
  style.spacing = 3.0;
  style.door_colours = {rgb(236, 236, 230), rgb(215, 210, 200)};
  style.patches = 0.3;
  style.bars = 0.3;
  decorate(w, {0, 0, 20, 13}, style, rng);
  const double xs[5] = {3, 6.5, 10, 13.5, 17}, ys[3] = {2.5, 6.5, 10.5};
  int index[5][3];
  int k = 0;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 5; ++i) {
      index[i][j] = static_cast<int>(s.points.size());
      add_point(s, rng, numbered('m', k++), true, {xs[i] + rng.uniform(-0.1, 0.1), ys[j] + rng.uniform(-0.1, 0.1)},
                config);
    }
  }
  // 18 test points: the centre of each of the 8 grid squares (adjacent to its 4 corners) and the
  // middle of each of the 10 north-south grid edges (adjacent to its 2 ends).
  int t = 0;
  auto test_point = [&](Vec2 p, std::vector<int> adjacent) {
    add_point(s, rng, numbered('t', t++), false, p + Vec2{rng.uniform(-0.35, 0.35), rng.uniform(-0.35, 0.35)}, config);
    for (int m : adjacent) s.adjacency.push_back({static_cast<int>(s.points.size()) - 1, m});
  };
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 4; ++i) {
      test_point({(xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2},
                 {index[i][j], index[i + 1][j], index[i][j + 1], index[i + 1][j + 1]});
    }
  }
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 5; ++i) test_point({xs[i], (ys[j] + ys[j + 1]) / 2}, {index[i][j], index[i][j + 1]});
  }
  s.world = std::move(w);
  assign_places(s);
  return s;
}

}  // namespace

const std::vector<ScenarioInfo>& scenarios() {
  static const std::vector<ScenarioInfo> list{
      {"figure-eight", ScenarioKind::sequence,
       "mapping paper Fig. 1: a loop whose shared section is driven twice in the same direction (indoors, 0.25 m)"},
      {"corridor-reverse", ScenarioKind::sequence,
       "experiment 1: a corridor out, a loop round a stair well, the corridor back in reverse (indoors, 0.25 m)"},
      {"nested-loops", ScenarioKind::sequence,
       "experiment 2: three loops side by side, outdoors with one indoor corridor, 70 x 35 m (0.5 m)"},
      {"zigzag", ScenarioKind::sequence,
       "experiment 3: the two left loops of nested-loops, driven again zig-zagging (0.5 m)"},
      {"aliasing", ScenarioKind::sequence,
       "three identical corridors in a serpentine: no revisit, only false loop closures to avoid (0.25 m)"},
      {"rooms", ScenarioKind::survey,
       "localization paper: ten separate rooms, one map and three test panoramas near each centre"},
      {"ground-floor", ScenarioKind::survey,
       "localization paper Fig. 7 left: entry hall to conference room, 21 map and 22 test points"},
      {"white-hall", ScenarioKind::survey,
       "localization paper Fig. 7 right: a white entrance hall, 15 map and 18 test points"},
  };
  return list;
}

ScenarioSetup build_scenario(const std::string& name, const SimulationConfig& config) {
  ScenarioSetup s;
  if (name == "figure-eight")
    s = figure_eight(config);
  else if (name == "corridor-reverse")
    s = corridor_reverse(config);
  else if (name == "nested-loops")
    s = nested_loops(config);
  else if (name == "zigzag")
    s = zigzag(config);
  else if (name == "aliasing")
    s = aliasing(config);
  else if (name == "rooms")
    s = rooms(config);
  else if (name == "ground-floor")
    s = ground_floor(config);
  else if (name == "white-hall")
    s = white_hall(config);
  else
    throw std::invalid_argument("unknown scenario '" + name + "' (see --list)");
  if (config.interval) s.interval = *config.interval;
  const double f = config.odometry_noise;
  if (f < 0) throw std::invalid_argument("odometry noise factor must be >= 0");
  s.odometry = {s.odometry.scale_error * f, s.odometry.heading_drift * f, s.odometry.translation_sigma * f,
                s.odometry.rotation_sigma * f};
  if (config.scale_error) s.odometry.scale_error = *config.scale_error;
  if (config.heading_drift) s.odometry.heading_drift = *config.heading_drift;
  return s;
}

SimulatedRun simulate(const ScenarioSetup& setup, const SimulationConfig& config) {
  if (!(setup.interval > 0)) throw std::invalid_argument("the recording interval must be > 0");
  if (config.panorama.width <= 0 || config.panorama.height <= 0 || config.panorama.supersample <= 0 ||
      config.camera.width <= 0 || config.camera.height <= 0 || config.camera.supersample <= 0) {
    throw std::invalid_argument("image sizes and supersampling must be positive");
  }
  SimulatedRun run;
  run.scenario = setup.name;
  run.kind = setup.kind;
  run.interval = setup.interval;
  const int threads = config.threads > 0 ? config.threads : omp_get_max_threads();
  if (setup.kind == ScenarioKind::survey) {
    run.points = setup.points;
    run.adjacency = setup.adjacency;
    for (const SurveyPoint& p : run.points) {
      if (setup.world.solid_at({p.pose.x, p.pose.y}))
        throw std::logic_error(setup.name + ": point " + p.id + " is inside a wall");
    }
    run.panoramas.resize(run.points.size());
    const auto n = static_cast<std::ptrdiff_t>(run.points.size());
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      const auto i = static_cast<std::size_t>(k);
      run.panoramas[i] = render_panorama(setup.world, run.points[i].pose, config.panorama, setup.point_lighting[i],
                                         hash_combine(config.seed, hash_combine(3, i)));
    }
    run.floor_plan = draw_floor_plan(setup, run);
    return run;
  }

  std::vector<RouteFrame> frames = follow_route(setup.graph, setup.legs, setup.interval);
  if (config.max_frames > 0 && frames.size() > config.max_frames) frames.resize(config.max_frames);
  std::map<int, int> compact;  // raw place -> id in order of first visit
  for (const RouteFrame& f : frames) {
    run.poses.push_back(f.pose);
    run.on_path.push_back(f.on_path);
    run.traversals.push_back(f.leg);
    const int raw = raw_place(setup.graph, config.places, f.edge, f.along);
    const auto it = compact.emplace(raw, static_cast<int>(compact.size())).first;
    run.places.push_back(it->second);
  }
  // Junctions: nodes where three or more of the route's edges meet.
  std::set<int> used_edges;
  for (const RouteLeg& leg : setup.legs) {
    for (std::size_t k = 0; k + 1 < leg.nodes.size(); ++k)
      used_edges.insert(setup.graph.edge_between(leg.nodes[k], leg.nodes[k + 1]));
  }
  std::vector<int> degree(setup.graph.nodes.size(), 0);
  for (int e : used_edges) {
    ++degree[static_cast<std::size_t>(setup.graph.edges[static_cast<std::size_t>(e)][0])];
    ++degree[static_cast<std::size_t>(setup.graph.edges[static_cast<std::size_t>(e)][1])];
  }
  for (std::size_t v = 0; v < degree.size(); ++v) {
    const auto it = compact.find(static_cast<int>(v));  // node places have the node's index as raw id
    if (degree[v] >= 3 && it != compact.end()) run.junctions.push_back(it->second);
  }
  std::sort(run.junctions.begin(), run.junctions.end());
  for (std::size_t k = 0; k < run.poses.size(); ++k) {
    if (setup.world.solid_at({run.poses[k].x, run.poses[k].y})) {
      throw std::logic_error(setup.name + ": frame " + std::to_string(k) + " is inside a wall");
    }
  }
  run.odometry = simulate_odometry(run.poses, setup.odometry, config.seed);

  const auto n = static_cast<std::ptrdiff_t>(frames.size());
  run.panoramas.resize(frames.size());
  if (config.forward_images) run.images.resize(frames.size());
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    Lighting lighting = setup.legs[static_cast<std::size_t>(frames[i].leg)].lighting;
    lighting.noise_sigma = config.pixel_noise;
    run.panoramas[i] = render_panorama(setup.world, frames[i].pose, config.panorama, lighting,
                                       hash_combine(config.seed, hash_combine(1, i)));
    if (config.forward_images) {
      run.images[i] = render_pinhole(setup.world, frames[i].pose, config.camera, lighting,
                                     hash_combine(config.seed, hash_combine(2, i)));
    }
  }
  run.floor_plan = draw_floor_plan(setup, run);
  return run;
}

DenseMatrix<std::uint8_t> same_place_matrix(const SimulatedRun& run, double radius, std::size_t band) {
  const std::size_t n = run.on_path.size();
  DenseMatrix<std::uint8_t> m(n, n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + band; j < n; ++j) {
      if (j - i < std::max<std::size_t>(band, 1)) continue;
      if (distance(run.on_path[i], run.on_path[j]) <= radius) m(i, j) = m(j, i) = 255;
    }
  }
  return m;
}

}  // namespace seqtopo::simulator
