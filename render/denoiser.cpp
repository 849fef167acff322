// Variance-guided edge-avoiding a-trous filter on albedo-demodulated radiance (see denoiser.h).
//
// Layout for speed: every per-pixel quantity is its own float plane (structure of arrays), padded by the filter's
// reach on every side with pixels of class -1 that no tap accepts, so the inner loops run over whole rows with no
// bounds checks and the compiler vectorises them (with an AVX2 clone where the CPU has it). Each output pixel is a
// fixed sum over its neighbours, so the result does not depend on the number of threads.
#include "render/denoiser.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace wobble::render {

namespace {

constexpr float kAlbedoFloor = 1e-3f;  // demodulation divides by max(albedo, this): exactly undone afterwards

// exp(x) for x <= 0 to about 1e-4 relative: 2^(integer part) from the exponent bits, 2^(fraction) by a polynomial.
// Plain float and int operations only, so the loops that call it vectorise.
inline float fastExp(float x) {
  const float t = std::max(x, -80.0f) * 1.44269504f;     // log2(e)
  const int whole = static_cast<int>(t + 128.0f) - 128;  // floor(t): t + 128 > 0 truncates downwards
  const float f = t - static_cast<float>(whole);         // [0, 1)
  const float p = 1.0f + f * (0.69314718f + f * (0.24022650f + f * (0.05550411f + f * 0.00961813f)));
  return p * std::bit_cast<float>((whole + 127) << 23);
}

// std::allocator without value-initialisation: planes are filled in parallel right after allocation, so zeroing
// tens of megabytes on one thread first (a third of the filter's time at 720p) is wasted.
template <typename T>
struct UninitializedAllocator : std::allocator<T> {
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// A padded float plane.
struct Plane {
  std::vector<float, UninitializedAllocator<float>> v;
  float* row(int y, int stride) { return v.data() + std::size_t(y) * stride; }
  const float* row(int y, int stride) const { return v.data() + std::size_t(y) * stride; }
};

// The signal being filtered: colour channels and the variance of its luminance.
struct Signal {
  Plane r, g, b, var;
};

struct Guide {
  Plane cls, z, gx, gy, nx, ny, nz;  // cls: 1 surface, 0 sky, -1 padding
  Plane blur, order;                 // the lens's blur radius (pixels); depth for occlusion, the sky farthest
  Plane mx, my, whole;               // the motion over the shutter (pixels); 1 where blurred by a pixel or more
};

// fn(begin, end) over [0, n) in blocks of 64 Ki values, on threads: for filling and copying whole planes.
template <typename Fn>
void forBlocks(std::size_t n, const Fn& fn) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16),
                    [&](const tbb::blocked_range<std::size_t>& range) { fn(range.begin(), range.end()); });
}

// Every plane of a call, kept from one frame to the next (per calling thread): a 720p frame needs about 25 planes
// of 4 MB, and fresh memory costs a page fault per 4 KB and a zero fill. The padding is filled once, when the size
// changes; each call writes every interior pixel it reads.
struct Workspace {
  std::size_t padded = 0;
  Guide guide;
  Signal diffuse, other, next;
  Plane inv, lum, filled;

  void resize(std::size_t size) {
    if (size == padded) return;
    padded = size;
    const auto fill = [&](Plane& plane, float value) {
      plane.v.resize(size);
      forBlocks(size, [&](std::size_t begin, std::size_t end) {
        std::fill(plane.v.data() + begin, plane.v.data() + end, value);
      });
    };
    fill(guide.cls, -1), fill(guide.z, 0), fill(guide.gx, 0), fill(guide.gy, 0);
    fill(guide.nx, 0), fill(guide.ny, 0), fill(guide.nz, 1);
    fill(guide.blur, 0), fill(guide.order, 0), fill(guide.mx, 0), fill(guide.my, 0), fill(guide.whole, 0);
    for (Signal* signal : {&diffuse, &other, &next})
      for (Plane* plane : {&signal->r, &signal->g, &signal->b, &signal->var}) fill(*plane, 0);
    fill(inv, 0), fill(lum, 0), fill(filled, 0);
  }
};

// dst = src, plane by plane, on threads.
void copySignal(const Signal& src, Signal& dst) {
  const auto copy = [](const Plane& from, Plane& to) {
    forBlocks(from.v.size(), [&](std::size_t begin, std::size_t end) {
      std::copy(from.v.data() + begin, from.v.data() + end, to.v.data() + begin);
    });
  };
  copy(src.r, dst.r), copy(src.g, dst.g), copy(src.b, dst.b), copy(src.var, dst.var);
}

template <typename Body>
void forRows(int begin, int end, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(begin, end), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) body(y);
  });
}

inline float lum(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

// The planes one pass reads, at the first pixel of a row span.
struct TapInput {
  const float *cls, *z, *gx, *gy, *nx, *ny, *nz;  // guides
  const float *blur, *order, *mx, *my, *whole;    // depth of field and motion blur (read when kBlur)
  const float *r, *g, *b, *var;                   // the signal
  const float* inv;                               // 1 / (sigma_l sqrt(blurred variance) + eps) at the output pixel
};
struct TapSums {
  float *r, *g, *b, *var;
};

// The taps of one iteration besides the centre: offset in the padded plane, offset in pixels, kernel weight.
struct Taps {
  static constexpr int kMax = 24;  // 5 x 5 - 1
  int count = 0;
  std::ptrdiff_t offset[kMax];
  float dx[kMax], dy[kMax], d2[kMax], k[kMax];  // d2: squared distance in pixels
};

// One iteration for a span of n output pixels: every tap's weighted value, weight and squared-weight variance,
// summed in registers and written once (the taps in the inner loop, so each pixel's own guides are loaded once).
// kTaps is the tap count, a constant so that the inner loop unrolls and the outer one vectorises.
// Depth of field and motion blur (kBlur): a pixel's lens or shutter samples see, near an edge, the nearer surface or
// what lies behind it, in shares that change over the nearer surface's blur, not from pixel to pixel: over its circle
// of confusion (in pixels), and along the way its image moves while the shutter is open. So a tap q counts with its
// kernel weight alone, whatever the surfaces, when it lies within the blur of the nearer of x and q, if that is a
// pixel or more: within the circle, or within half the motion along it (and within 30 degrees of its direction, so
// that one pair of the 8 tap directions always qualifies). A blurred foreground and what is seen past it mix both
// ways; an in-focus or still edge stays sharp against a blurred background (its own blur is small). Both must carry
// their whole colour: blurred pixels (not demodulated, denoise() below) and the sky. Otherwise the usual weights,
// between surfaces alike blurred or sharp; sky pixels no tap reaches stay as rendered. Without kBlur nothing of this
// is read.
template <int kTaps, bool kBlur>
__attribute__((target_clones("avx512f", "avx2", "default"))) void filterSpan(const TapInput in, const TapSums out,
                                                                             int n, const Taps taps, float centre,
                                                                             float sigma_n, float sigma_z) {
  // The planes never overlap; GCC ignores restrict on locals, so `ivdep` says it (too many planes for run-time alias
  // checks otherwise, and the loop would stay scalar).
  const float* __restrict cls = in.cls, * __restrict z = in.z, * __restrict gx = in.gx, * __restrict gy = in.gy;
  const float* __restrict nx = in.nx, * __restrict ny = in.ny, * __restrict nz = in.nz;
  const float* __restrict rb = in.blur, * __restrict zo = in.order;
  const float* __restrict mx = in.mx, * __restrict my = in.my, * __restrict whole = in.whole;
  const float* __restrict ir = in.r, * __restrict ig = in.g, * __restrict ib = in.b, * __restrict iv = in.var;
  const float* __restrict inv = in.inv;
  float* __restrict sr = out.r, * __restrict sg = out.g, * __restrict sb = out.b, * __restrict sv = out.var;
#pragma GCC ivdep
  for (int x = 0; x < n; ++x) {
    const float lp = lum(ir[x], ig[x], ib[x]);
    float r = centre * ir[x], g = centre * ig[x], b = centre * ib[x], wsum = centre, var = centre * centre * iv[x];
#pragma GCC unroll 24
    for (int t = 0; t < kTaps; ++t) {
      const std::ptrdiff_t q = x + taps.offset[t];
      const float expected = std::abs(gx[x] * taps.dx[t] + gy[x] * taps.dy[t]);
      const float normal = nx[x] * nx[q] + ny[x] * ny[q] + nz[x] * nz[q];
      const float geometry =
          std::abs(z[x] - z[q]) / (sigma_z * expected + 0.01f * z[x] + 1e-6f) + sigma_n * std::max(0.0f, 1.0f - normal);
      float same = cls[x] == cls[q] ? taps.k[t] : 0.0f;
      const float l = std::abs(lp - lum(ir[q], ig[q], ib[q]));
      float w;
      if constexpr (kBlur) {
        // Bitwise & and |, not && and ||: no branches, so the loop vectorises.
        const bool bx = whole[x] != 0.0f, bq = whole[q] != 0.0f;
        const bool whole_x = bx | (cls[x] == 0.0f), whole_q = bq | (cls[q] == 0.0f);
        // The blur of the nearer of the two: the lens's, and the motion's along (d.m) and across (d x m) it.
        const bool q_nearer = zo[q] <= zo[x];
        const float near = q_nearer ? rb[q] : rb[x];
        const float mnx = q_nearer ? mx[q] : mx[x], mny = q_nearer ? my[q] : my[x], m2 = mnx * mnx + mny * mny;
        const float along = taps.dx[t] * mnx + taps.dy[t] * mny, across = taps.dx[t] * mny - taps.dy[t] * mnx;
        const bool lens = (near >= 1.0f) & (taps.d2[t] <= near * near);
        const bool motion = (m2 >= 1.0f) & (4 * along * along + across * across <= m2 * m2);
        const bool spread = whole_x & whole_q & (lens | motion);
        same = (bx == bq) & (cls[x] == 1.0f) ? same : 0.0f;
        w = spread ? taps.k[t] : same * fastExp(-geometry - l * inv[x]);
      } else {
        w = same * fastExp(-geometry - l * inv[x]);
      }
      r += w * ir[q], g += w * ig[q], b += w * ib[q];
      wsum += w, var += w * w * iv[q];
    }
    // Only surfaces are filtered: the sky seen directly is exact up to anti-aliasing, and stays as rendered (unless
    // the lens or the motion of what is in front blurs it).
    const float iw = 1.0f / wsum;
    bool surface = cls[x] == 1.0f;
    if constexpr (kBlur) surface = surface | (wsum > centre);  // the sky where a blurred tap reaches it
    sr[x] = surface ? r * iw : ir[x], sg[x] = surface ? g * iw : ig[x], sb[x] = surface ? b * iw : ib[x];
    sv[x] = surface ? var * iw * iw : iv[x];
  }
}

// The output pixels a signal is filtered over (image coordinates, half-open); empty when x1 <= x0.
struct Window {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  void add(int x, int y) {
    if (x1 <= x0) {
      *this = {x, x + 1, y, y + 1};
      return;
    }
    x0 = std::min(x0, x), x1 = std::max(x1, x + 1), y0 = std::min(y0, y), y1 = std::max(y1, y + 1);
  }
  bool empty() const { return x1 <= x0; }
  void merge(const Window& o) {
    if (o.empty()) return;
    if (empty()) {
      *this = o;
      return;
    }
    x0 = std::min(x0, o.x0), x1 = std::max(x1, o.x1), y0 = std::min(y0, o.y0), y1 = std::max(y1, o.y1);
  }
};

// Where a pixel has one sample its variance is unknown (-1): the luminance variance over its 3 x 3 neighbourhood
// (padding counts as zero; large at silhouettes, which keeps the filter off them). l and filled are scratch planes
// whose padding is zero; filled is swapped with s.var.
void fillMissingVariance(Signal& s, Plane& l, Plane& filled, int stride, int pad, int w, int h) {
  forRows(pad, pad + h, [&](int y) {
    const float *r = s.r.row(y, stride), *g = s.g.row(y, stride), *b = s.b.row(y, stride);
    float* out = l.row(y, stride);
    for (int x = pad; x < pad + w; ++x) out[x] = lum(r[x], g[x], b[x]);
  });
  forRows(pad, pad + h, [&](int y) {
    const float* up = l.row(y - 1, stride);
    const float* mid = l.row(y, stride);
    const float* down = l.row(y + 1, stride);
    float* out = filled.row(y, stride);
    const float* known = s.var.row(y, stride);
    for (int x = pad; x < pad + w; ++x) {
      float sum = 0, sq = 0;
      for (int dx = -1; dx <= 1; ++dx)
        for (const float* r : {up, mid, down}) sum += r[x + dx], sq += r[x + dx] * r[x + dx];
      const float m = sum / 9.0f;
      out[x] = known[x] >= 0 ? known[x] : std::max(0.0f, sq / 9.0f - m * m);
    }
  });
  std::swap(s.var, filled);
}

// 1 / (sigma_l sqrt(3 x 3 Gaussian of the variance) + eps) per pixel of row y, columns x0..x1 (padded
// coordinates): the luminance weight's scale. Cloned like filterSpan: its square root and division vectorise 16 wide
// with AVX-512 (exact operations: the same bits in every clone).
__attribute__((target_clones("avx512f", "avx2", "default"))) void inverseDeviation(const Plane& var, Plane& out,
                                                                                   float sigma, int stride, int x0,
                                                                                   int x1, int y) {
  const float* up = var.row(y - 1, stride);
  const float* mid = var.row(y, stride);
  const float* down = var.row(y + 1, stride);
  float* o = out.row(y, stride);
  for (int x = x0; x < x1; ++x) {
    const float blurred = (up[x - 1] + 2 * up[x] + up[x + 1] + 2 * (mid[x - 1] + 2 * mid[x] + mid[x + 1]) +
                           down[x - 1] + 2 * down[x] + down[x + 1]) /
                          16.0f;
    o[x] = 1.0f / (sigma * std::sqrt(blurred) + 1e-4f);
  }
}

// The pixels a motion-blurred edge sweeps (1) over the shutter. An edge pixel sees the sky where a neighbour sees a
// surface or the reverse, or moves a pixel or more differently from it; the band is the pixels along an edge pixel's
// motion, half of it either way, whatever they see themselves (a still background's pixels too). Only there do one
// instant's samples dither between what is in front and what is behind; elsewhere a moving surface's pixels agree
// with their neighbours, and the usual weights (and the texture divided out) serve them better. Marked in pixel
// order: the same whatever the threads.
std::vector<char> sweptByMotion(const image::Film& film) {
  const int w = film.width, h = film.height;
  std::vector<char> edge(film.motion.size(), 0), band(film.motion.size(), 0);
  forRows(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = film.index(x, y);
      const bool sky = !std::isfinite(film.depth[i]);
      const auto differs = [&](std::size_t q) {
        return !std::isfinite(film.depth[q]) != sky || (film.motion[q] - film.motion[i]).squaredNorm() >= 1.0f;
      };
      edge[i] = (x > 0 && differs(i - 1)) || (x + 1 < w && differs(i + 1)) || (y > 0 && differs(i - w)) ||
                (y + 1 < h && differs(i + w));
    }
  });
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t i = film.index(x, y);
      const Eigen::Vector2f m = film.motion[i];
      if (!edge[i] || m.squaredNorm() < 1.0f) continue;
      const int steps = static_cast<int>(std::ceil(0.5f * m.norm()));  // at most a pixel apart
      for (int k = -steps; k <= steps; ++k) {
        const Eigen::Vector2f at = Eigen::Vector2f(float(x), float(y)) + (0.5f * float(k) / float(steps)) * m;
        const int qx = static_cast<int>(std::lround(at.x())), qy = static_cast<int>(std::lround(at.y()));
        if (qx >= 0 && qy >= 0 && qx < w && qy < h) band[film.index(qx, qy)] = 1;
      }
    }
  return band;
}

}  // namespace

std::vector<Color> denoise(const image::Film& film, const DenoiseSettings& settings) {
  const int w = film.width, h = film.height;
  const std::size_t n = std::size_t(w) * h;
  if (w <= 0 || h <= 0 || film.color.size() != n || film.albedo.size() != n || film.normal.size() != n ||
      film.depth.size() != n || film.diffuse.size() != n || film.variance_diffuse.size() != n ||
      film.variance_other.size() != n || (!film.blur.empty() && film.blur.size() != n) ||
      (!film.motion.empty() && film.motion.size() != n))
    throw std::invalid_argument("denoise: empty or inconsistent film");
  if (settings.iterations < 0 || settings.iterations > 10 || settings.radius < 1 || settings.radius > 2 ||
      !(settings.sigma_luminance > 0) || !(settings.sigma_normal >= 0) || !(settings.sigma_depth > 0) ||
      settings.well_sampled < 0 || settings.well_sampled_iterations < 0)
    throw std::invalid_argument(
        "denoise: need iterations in [0, 10], radius 1 or 2, sigma_luminance > 0, "
        "sigma_normal >= 0, sigma_depth > 0, well_sampled >= 0, well_sampled_iterations >= 0");

  const int pad = std::max(1, settings.iterations > 0 ? settings.radius << (settings.iterations - 1) : 0);
  const int stride = w + 2 * pad, rows = h + 2 * pad;
  const std::size_t padded = std::size_t(stride) * rows;
  thread_local Workspace ws;
  ws.resize(padded);
  const auto at = [&](int x, int y) { return std::size_t(y + pad) * stride + (x + pad); };

  // Guides: class, depth and its screen-space gradient, normal (sky pixels get a fixed normal and depth 0, so only
  // their class keeps them apart from surfaces).
  Guide& guide = ws.guide;
  Signal &diffuse = ws.diffuse, &other = ws.other;
  // Only surfaces need filtering (the sky seen directly is exact up to anti-aliasing), and of `other` only where
  // it is not zero: the coat's reflections (usually a small part of the frame).
  std::vector<Window> row_surfaces(h), row_coated(h);  // per row, merged below (rows are filled in parallel)
  // Depth of field and motion blur: pixels the lens blurs by a pixel or more, and those a moving edge sweeps
  // (sweptByMotion), are filtered whole (colour in `other`, no demodulation: their texture is blurred anyway,
  // and a blurred pixel whose sample saw the sky has no albedo to divide by).
  const bool lens =
      !film.blur.empty() && std::any_of(film.blur.begin(), film.blur.end(), [](float r) { return r >= 1.0f; });
  const bool moving = !film.motion.empty() && std::any_of(film.motion.begin(), film.motion.end(),
                                                          [](const auto& m) { return m.squaredNorm() >= 1.0f; });
  const bool blur_any = lens || moving;
  const std::vector<char> swept = moving ? sweptByMotion(film) : std::vector<char>();
  std::vector<Window> row_blurred(h);  // per row, the blurred pixels' columns
  forRows(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = film.index(x, y), p = at(x, y);
      const bool sky = !std::isfinite(film.depth[i]);
      const float blur = lens ? film.blur[i] : 0.0f;
      const Eigen::Vector2f motion = moving ? film.motion[i] : Eigen::Vector2f::Zero();
      guide.cls.v[p] = sky ? 0.0f : 1.0f;
      guide.blur.v[p] = blur, guide.order.v[p] = sky ? std::numeric_limits<float>::max() : film.depth[i];
      guide.mx.v[p] = motion.x(), guide.my.v[p] = motion.y();
      const bool blurred = blur >= 1.0f || (moving && swept[i]);
      guide.whole.v[p] = blurred ? 1.0f : 0.0f;
      if (blurred) row_blurred[y].add(x, y);
      const Color d =
          blurred ? Color::Zero() : Color(film.diffuse[i].cwiseQuotient(film.albedo[i].cwiseMax(kAlbedoFloor)));
      const Color o = blurred ? film.color[i] : Color(film.color[i] - film.diffuse[i]);
      guide.z.v[p] = sky ? 0.0f : film.depth[i];
      guide.nx.v[p] = sky ? 0.0f : film.normal[i].x(), guide.ny.v[p] = sky ? 0.0f : film.normal[i].y();
      guide.nz.v[p] = sky ? 1.0f : film.normal[i].z();
      if (!sky || lens || blurred) {
        row_surfaces[y].add(x, y);
        if (!o.isZero()) row_coated[y].add(x, y);
      }
      diffuse.r.v[p] = d.x(), diffuse.g.v[p] = d.y(), diffuse.b.v[p] = d.z(),
      diffuse.var.v[p] = film.variance_diffuse[i];
      other.r.v[p] = o.x(), other.g.v[p] = o.y(), other.b.v[p] = o.z(), other.var.v[p] = film.variance_other[i];
    }
  });
  Window surfaces, coated;
  for (int y = 0; y < h; ++y) {
    surfaces.merge(row_surfaces[y]);
    coated.merge(row_coated[y]);
  }
  // Depth gradient: per axis the smaller one-sided difference to a surface neighbour, so it does not jump at
  // silhouettes.
  forRows(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t p = at(x, y);
      guide.gx.v[p] = guide.gy.v[p] = 0;
      if (guide.cls.v[p] != 1.0f) continue;
      const auto slope = [&](std::size_t before, std::size_t after) {
        const bool fb = guide.cls.v[before] == 1.0f, fa = guide.cls.v[after] == 1.0f;
        const float a = guide.z.v[p] - guide.z.v[before], b = guide.z.v[after] - guide.z.v[p];
        if (fb && fa) return std::abs(a) < std::abs(b) ? a : b;
        return fb ? a : fa ? b : 0.0f;
      };
      guide.gx.v[p] = slope(p - 1, p + 1);
      guide.gy.v[p] = slope(p - stride, p + stride);
    }
  });
  fillMissingVariance(diffuse, ws.lum, ws.filled, stride, pad, w, h);
  fillMissingVariance(other, ws.lum, ws.filled, stride, pad, w, h);
  // Well-sampled surface pixels (denoiser.h): held as they are after the first iterations. None on a frame of one to a
  // few samples a pixel.
  std::vector<std::size_t> held;
  if (settings.well_sampled > 0 && settings.well_sampled_iterations < settings.iterations && film.samples.size() == n)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t p = at(x, y);
        if (film.samples[film.index(x, y)] >= std::uint32_t(settings.well_sampled) && guide.cls.v[p] == 1.0f &&
            guide.whole.v[p] == 0.0f)
          held.push_back(p);
      }

  const float b3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
  const float b1[3] = {1.0f / 4, 1.0f / 2, 1.0f / 4};
  const float* kernel = settings.radius == 2 ? b3 : b1;
  const int r = settings.radius;
  Plane& inv = ws.inv;
  // One a-trous iteration of one signal over its window, from `in` into `out` (pixels outside the window keep their
  // values: both buffers start equal and only the window is written). With `spans`, each row only over its own span
  // of the window (the diffuse signal: beyond a row's first and last surface pixel there is only sky, which the
  // filter leaves as it is).
  const auto pass = [&](const Signal& in, Signal& out, const Window& window, const std::vector<Window>* spans,
                        int step) {
    Taps taps;
    for (int ky = -r; ky <= r; ++ky)
      for (int kx = -r; kx <= r; ++kx) {
        if (kx == 0 && ky == 0) continue;
        const int dx = kx * step, dy = ky * step;
        taps.offset[taps.count] = std::ptrdiff_t(dy) * stride + dx;
        taps.dx[taps.count] = float(dx), taps.dy[taps.count] = float(dy),
        taps.d2[taps.count] = float(dx * dx + dy * dy);
        taps.k[taps.count++] = kernel[kx + r] * kernel[ky + r];
      }
    forRows(window.y0, window.y1, [&](int y) {
      const Window& row = spans ? (*spans)[y] : window;
      if (row.empty()) return;
      inverseDeviation(in.var, inv, settings.sigma_luminance, stride, row.x0 + pad, row.x1 + pad, y + pad);
      const float centre = kernel[r] * kernel[r];
      const float sn = settings.sigma_normal, sz = settings.sigma_depth;
      // Columns [x0, x1) of the row, with or without the blur's rules.
      const auto filter = [&](int x0, int x1, bool blur) {
        if (x1 <= x0) return;
        const std::size_t first = at(x0, y);
        const TapInput tap_in{guide.cls.v.data() + first, guide.z.v.data() + first,    guide.gx.v.data() + first,
                              guide.gy.v.data() + first,  guide.nx.v.data() + first,   guide.ny.v.data() + first,
                              guide.nz.v.data() + first,  guide.blur.v.data() + first, guide.order.v.data() + first,
                              guide.mx.v.data() + first,  guide.my.v.data() + first,   guide.whole.v.data() + first,
                              in.r.v.data() + first,      in.g.v.data() + first,       in.b.v.data() + first,
                              in.var.v.data() + first,    inv.v.data() + first};
        const TapSums sums{out.r.v.data() + first, out.g.v.data() + first, out.b.v.data() + first,
                           out.var.v.data() + first};
        if (r == 1) (blur ? filterSpan<8, true> : filterSpan<8, false>)(tap_in, sums, x1 - x0, taps, centre, sn, sz);
        else (blur ? filterSpan<24, true> : filterSpan<24, false>)(tap_in, sums, x1 - x0, taps, centre, sn, sz);
      };
      // Only columns with a blurred pixel within this iteration's taps take the blur's rules (elsewhere they give
      // the plain kernel's values, slower).
      const int taps_reach = r * step;
      Window near;
      for (int dy = -taps_reach; dy <= taps_reach && blur_any; ++dy)
        if (y + dy >= 0 && y + dy < h) near.merge(row_blurred[y + dy]);
      const int b0 = near.empty() ? row.x1 : std::clamp(near.x0 - taps_reach, row.x0, row.x1);
      const int b1x = near.empty() ? row.x1 : std::clamp(near.x1 + taps_reach, b0, row.x1);
      filter(row.x0, b0, false), filter(b0, b1x, true), filter(b1x, row.x1, false);
    });
  };
  using Job = std::tuple<Signal*, Window, const std::vector<Window>*>;
  for (const auto& [signal, window, spans] : {Job{&diffuse, surfaces, &row_surfaces}, Job{&other, coated, nullptr}}) {
    if (window.empty()) continue;
    Signal& next = ws.next;
    copySignal(*signal, next);
    for (int iteration = 0; iteration < settings.iterations; ++iteration) {
      pass(*signal, next, window, spans, 1 << iteration);
      if (iteration >= settings.well_sampled_iterations)
        for (const std::size_t p : held) {
          next.r.v[p] = signal->r.v[p], next.g.v[p] = signal->g.v[p], next.b.v[p] = signal->b.v[p];
          next.var.v[p] = signal->var.v[p];
        }
      std::swap(*signal, next);
    }
  }

  std::vector<Color> out(n);
  forRows(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = film.index(x, y), p = at(x, y);
      out[i] =
          Color(diffuse.r.v[p], diffuse.g.v[p], diffuse.b.v[p]).cwiseProduct(film.albedo[i].cwiseMax(kAlbedoFloor)) +
          Color(other.r.v[p], other.g.v[p], other.b.v[p]);
    }
  });
  return out;
}

}  // namespace wobble::render
