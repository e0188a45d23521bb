#include "seqtopo/simulator/render.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "seqtopo/simulator/random.hpp"

namespace seqtopo::simulator {
namespace {

// Brightness depends only on a face's axis: a place looks the same whichever way it is passed, and a
// corridor turned through 180 degrees looks like the original (the aliasing scenario relies on it).
float side_shade(Side side) { return side == Side::west || side == Side::east ? 0.8F : 0.95F; }

// Gentle fall-off with distance: a depth cue, and distant clutter fades instead of flickering.
Colour attenuate(Colour c, double d, float shade) {
  const float f = shade * static_cast<float>(0.7 + 0.3 * std::exp(-d / 12.0));
  return {c[0] * f, c[1] * f, c[2] * f};
}

Colour sky_colour(const GridWorld& w, double slope) {
  const float t = static_cast<float>(std::min(1.0, slope * 3.0));
  return {w.horizon[0] + (w.sky[0] - w.horizon[0]) * t, w.horizon[1] + (w.sky[1] - w.horizon[1]) * t,
          w.horizon[2] + (w.sky[2] - w.horizon[2]) * t};
}

// Colours of one vertical column of rays from `origin` along `angle`: slope[k] = tan(elevation) of row
// k, descending (top row first). Surfaces are met in order of distance, so each row is coloured by the
// first surface it meets: rows still open always form one band [top, bottom], the floor closing it from
// below and the ceiling from above.
void trace_column(const GridWorld& w, Vec2 o, double angle, double cam_h, const double* slope, int n, Colour* out) {
  int top = 0, bot = n - 1;
  const double dx = std::cos(angle), dy = std::sin(angle);
  int cx = w.cell_x(o.x), cy = w.cell_y(o.y);
  const double cell = w.cell_size();
  const double inf = std::numeric_limits<double>::infinity();
  if (w.inside(cx, cy)) {
    const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    double t_max_x = dx != 0 ? (w.bounds().x0 + (cx + (step_x > 0 ? 1 : 0)) * cell - o.x) / dx : inf;
    double t_max_y = dy != 0 ? (w.bounds().y0 + (cy + (step_y > 0 ? 1 : 0)) * cell - o.y) / dy : inf;
    const double t_delta_x = dx != 0 ? cell / std::abs(dx) : inf;
    const double t_delta_y = dy != 0 ? cell / std::abs(dy) : inf;
    double d0 = 0;
    Side side = Side::west;
    const double ceiling_h = w.ceiling_height;
    while (top <= bot) {
      const double d1 = std::min(t_max_x, t_max_y);
      const int mat = w.material_at(cx, cy);
      const Ground& g = w.ground(w.ground_at(cx, cy));
      if (mat == 0 || d0 == 0) {
        while (bot >= top && slope[bot] < 0) {
          const double d = cam_h / -slope[bot];
          if (d > d1) break;
          out[bot--] = attenuate(w.ground_colour(cx, cy, {o.x + d * dx, o.y + d * dy}), d, 0.92F);
        }
      } else {
        const Material& m = w.material(mat);
        const double u = (side == Side::west || side == Side::east) ? o.y + d0 * dy : o.x + d0 * dx;
        const float shade = side_shade(side);
        const GridWorld::Face face = w.face(cx, cy, side);
        while (bot >= top) {
          const double z = cam_h + d0 * slope[bot];
          if (z > m.height) break;
          out[bot--] = attenuate(w.face_colour(face, u, std::max(0.0, z)), d0, shade);
        }
        if (m.height < cam_h) {  // the top of a low block (cabinet, hedge) seen from above
          while (bot >= top && slope[bot] < 0) {
            const double d = (cam_h - m.height) / -slope[bot];
            if (d > d1) break;
            out[bot--] = attenuate(m.accent, d, 1.0F);
          }
        }
      }
      if (g.roofed) {
        while (top <= bot && slope[top] > 0) {
          const double d = (ceiling_h - cam_h) / slope[top];
          if (d > d1) break;
          out[top++] = attenuate(w.ceiling_colour({o.x + d * dx, o.y + d * dy}), d, 1.0F);
        }
      }
      if (t_max_x < t_max_y) {
        cx += step_x;
        d0 = t_max_x;
        t_max_x += t_delta_x;
        side = step_x > 0 ? Side::west : Side::east;
      } else {
        cy += step_y;
        d0 = t_max_y;
        t_max_y += t_delta_y;
        side = step_y > 0 ? Side::south : Side::north;
      }
      if (!w.inside(cx, cy)) break;
    }
  }
  for (int k = top; k <= bot; ++k) out[k] = slope[k] > 0 ? sky_colour(w, slope[k]) : w.horizon;
}

// Sum of four 16-bit uniforms, rescaled to unit variance: close enough to Gaussian for sensor noise and
// several times cheaper than Box-Muller, which dominated rendering time.
double approximate_normal(Rng& rng) {
  const std::uint64_t r = rng.next();
  const auto sum = static_cast<double>((r & 0xFFFF) + ((r >> 16) & 0xFFFF) + ((r >> 32) & 0xFFFF) + (r >> 48));
  return (sum / 65536.0 - 2.0) * 1.7320508075688772;  // sqrt(12 / 4)
}

// Box-filters the supersampled rays into pixels, applies the lighting and adds sensor noise (drawn in
// raster order from the image's own seed).
RgbImage finish(const std::vector<Colour>& rays, int width, int height, int s, const Lighting& lighting,
                std::uint64_t noise_seed) {
  RgbImage image(width, height);
  Rng rng(noise_seed, 0x1a9e);
  const int rows = height * s;
  const float inv = 1.0F / static_cast<float>(s * s);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      Colour sum{0, 0, 0};
      for (int a = 0; a < s; ++a) {
        for (int b = 0; b < s; ++b) {
          const int col = x * s + a, row = y * s + b;
          const Colour& c = rays[static_cast<std::size_t>(col) * rows + row];  // column-major
          sum[0] += c[0];
          sum[1] += c[1];
          sum[2] += c[2];
        }
      }
      std::uint8_t* p = image.at(x, y);
      for (int ch = 0; ch < 3; ++ch) {
        double v = sum[ch] * inv * lighting.gain * lighting.tint[ch];
        if (lighting.noise_sigma > 0) v += lighting.noise_sigma * approximate_normal(rng);
        p[ch] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      }
    }
  }
  return image;
}

void check_size(int width, int height, int supersample) {
  if (width <= 0 || height <= 0 || supersample <= 0) {
    throw std::invalid_argument("camera width, height and supersampling must be positive");
  }
}

}  // namespace

RgbImage render_panorama(const GridWorld& world, const Pose2& pose, const PanoramaCamera& camera,
                         const Lighting& lighting, std::uint64_t noise_seed) {
  check_size(camera.width, camera.height, camera.supersample);
  const int s = camera.supersample;
  const int cols = camera.width * s, rows = camera.height * s;
  std::vector<double> slope(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    const double e = camera.elevation_max - (r + 0.5) * (camera.elevation_max - camera.elevation_min) / rows;
    slope[static_cast<std::size_t>(r)] = std::tan(e);
  }
  std::vector<Colour> rays(static_cast<std::size_t>(cols) * rows);
  const double pi = std::numbers::pi;
  for (int c = 0; c < cols; ++c) {
    // Sub-columns are centred on the pixel: pixel column x looks at heading + 2*pi*x/width.
    const double angle = pose.theta + 2.0 * pi * (c + 0.5) / cols - pi / camera.width;
    trace_column(world, {pose.x, pose.y}, angle, camera.mount_height, slope.data(), rows,
                 rays.data() + static_cast<std::size_t>(c) * rows);
  }
  return finish(rays, camera.width, camera.height, s, lighting, noise_seed);
}

RgbImage render_pinhole(const GridWorld& world, const Pose2& pose, const PinholeCamera& camera,
                        const Lighting& lighting, std::uint64_t noise_seed) {
  check_size(camera.width, camera.height, camera.supersample);
  if (!(camera.horizontal_fov > 0 && camera.horizontal_fov < std::numbers::pi)) {
    throw std::invalid_argument("pinhole field of view must be in (0, pi)");
  }
  const int s = camera.supersample;
  const int cols = camera.width * s, rows = camera.height * s;
  const double f = 0.5 * cols / std::tan(0.5 * camera.horizontal_fov);  // focal length [sub-pixels]
  std::vector<double> slope(static_cast<std::size_t>(rows));
  std::vector<Colour> rays(static_cast<std::size_t>(cols) * rows);
  for (int c = 0; c < cols; ++c) {
    const double xc = 0.5 * cols - (c + 0.5);  // positive to the left
    const double along = std::hypot(f, xc);
    for (int r = 0; r < rows; ++r) slope[static_cast<std::size_t>(r)] = (0.5 * rows - (r + 0.5)) / along;
    trace_column(world, {pose.x, pose.y}, pose.theta + std::atan2(xc, f), camera.mount_height, slope.data(), rows,
                 rays.data() + static_cast<std::size_t>(c) * rows);
  }
  return finish(rays, camera.width, camera.height, s, lighting, noise_seed);
}

}  // namespace seqtopo::simulator
