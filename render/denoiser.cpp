// Variance-guided edge-avoiding a-trous filter on albedo-demodulated radiance (see denoiser.h).
#include "denoiser.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace wobble::render {

namespace {

constexpr float kB3[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
constexpr float kAlbedoFloor = 1e-3f;  // demodulation divides by max(albedo, this): exactly undone afterwards

// One of the two signals being filtered, with its per-pixel variance.
struct Signal {
  std::vector<Color> value;
  std::vector<float> variance;
};

template <typename Body>
void forRows(int height, const Body& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) body(y);
  });
}

// Where a pixel has one sample, its variance is unknown (-1): the luminance variance over its 3 x 3 neighbourhood.
void fillMissingVariance(Signal& s, int w, int h) {
  std::vector<float> filled = s.variance;
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (s.variance[i] >= 0) continue;
      float sum = 0, sq = 0;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const float l = luminance(s.value[std::size_t(ny) * w + nx]);
          sum += l, sq += l * l, ++n;
        }
      const float m = sum / float(n);
      filled[i] = std::max(0.0f, sq / float(n) - m * m);
    }
  });
  s.variance = std::move(filled);
}

// 3 x 3 Gaussian ([1 2 1] / 4 each way) of a variance image, clamped at the borders.
std::vector<float> blurVariance(const std::vector<float>& v, int w, int h) {
  std::vector<float> out(v.size());
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float sum = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = std::clamp(x + dx, 0, w - 1), ny = std::clamp(y + dy, 0, h - 1);
          sum += float((2 - std::abs(dx)) * (2 - std::abs(dy))) * v[std::size_t(ny) * w + nx];
        }
      out[std::size_t(y) * w + x] = sum / 16.0f;
    }
  });
  return out;
}

// The screen-space depth gradient: per axis the smaller one-sided difference, so it does not jump at silhouettes.
std::vector<Eigen::Vector2f> depthGradient(const std::vector<float>& z, int w, int h) {
  std::vector<Eigen::Vector2f> g(z.size(), Eigen::Vector2f::Zero());
  const auto slope = [](float before, float at, float after) {
    const float a = at - before, b = after - at;
    const bool fa = std::isfinite(a), fb = std::isfinite(b);
    if (fa && fb) return std::abs(a) < std::abs(b) ? a : b;
    return fa ? a : fb ? b : 0.0f;
  };
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = std::size_t(y) * w + x;
      if (!std::isfinite(z[i])) continue;
      const float inf = std::numeric_limits<float>::infinity();
      g[i] = {slope(x > 0 ? z[i - 1] : inf, z[i], x + 1 < w ? z[i + 1] : inf),
              slope(y > 0 ? z[i - w] : inf, z[i], y + 1 < h ? z[i + w] : inf)};
    }
  });
  return g;
}

}  // namespace

std::vector<Color> denoise(const Film& film, const DenoiseSettings& settings) {
  const int w = film.width, h = film.height;
  const std::size_t n = std::size_t(w) * h;
  if (w <= 0 || h <= 0 || film.color.size() != n || film.albedo.size() != n || film.normal.size() != n ||
      film.depth.size() != n || film.diffuse.size() != n || film.variance_diffuse.size() != n ||
      film.variance_other.size() != n)
    throw std::invalid_argument("denoise: empty or inconsistent film");
  if (settings.iterations < 0 || settings.iterations > 10 || !(settings.sigma_luminance > 0) ||
      !(settings.sigma_normal >= 0) || !(settings.sigma_depth > 0))
    throw std::invalid_argument("denoise: need iterations in [0, 10], sigma_luminance > 0, sigma_normal >= 0, "
                                "sigma_depth > 0");

  // The two signals: lighting under the diffuse lobe (demodulated) and the rest.
  Signal diffuse{std::vector<Color>(n), film.variance_diffuse}, other{std::vector<Color>(n), film.variance_other};
  for (std::size_t i = 0; i < n; ++i) {
    diffuse.value[i] = film.diffuse[i].cwiseQuotient(film.albedo[i].cwiseMax(kAlbedoFloor));
    other.value[i] = film.color[i] - film.diffuse[i];
  }
  fillMissingVariance(diffuse, w, h);
  fillMissingVariance(other, w, h);
  const std::vector<Eigen::Vector2f> gradient = depthGradient(film.depth, w, h);

  Signal next_diffuse = diffuse, next_other = other;
  for (int iteration = 0; iteration < settings.iterations; ++iteration) {
    const int step = 1 << iteration;
    const std::vector<float> blurred_d = blurVariance(diffuse.variance, w, h);
    const std::vector<float> blurred_o = blurVariance(other.variance, w, h);
    forRows(h, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const std::size_t p = std::size_t(y) * w + x;
        const float zp = film.depth[p];
        const bool sky_p = !std::isfinite(zp);
        const Eigen::Vector3f& np = film.normal[p];
        const float lp_d = luminance(diffuse.value[p]), lp_o = luminance(other.value[p]);
        const float inv_d = 1.0f / (settings.sigma_luminance * std::sqrt(blurred_d[p]) + 1e-4f);
        const float inv_o = 1.0f / (settings.sigma_luminance * std::sqrt(blurred_o[p]) + 1e-4f);
        Color sum_d = Color::Zero(), sum_o = Color::Zero();
        float weight_d = 0, weight_o = 0, var_d = 0, var_o = 0;
        for (int ky = -2; ky <= 2; ++ky) {
          const int qy = y + ky * step;
          if (qy < 0 || qy >= h) continue;
          for (int kx = -2; kx <= 2; ++kx) {
            const int qx = x + kx * step;
            if (qx < 0 || qx >= w) continue;
            const std::size_t q = std::size_t(qy) * w + qx;
            const float kernel = kB3[kx + 2] * kB3[ky + 2];
            float wd = kernel, wo = kernel;
            if (q != p) {
              const float zq = film.depth[q];
              if (sky_p != !std::isfinite(zq)) continue;  // sky and surface never mix
              float geometry = 0;
              if (!sky_p) {
                const float expected = std::abs(gradient[p].x() * float(kx * step) + gradient[p].y() * float(ky * step));
                geometry = std::abs(zp - zq) / (settings.sigma_depth * expected + 0.01f * std::abs(zp) + 1e-6f) +
                           settings.sigma_normal * std::max(0.0f, 1.0f - np.dot(film.normal[q]));
              }
              wd *= std::exp(-geometry - std::abs(lp_d - luminance(diffuse.value[q])) * inv_d);
              wo *= std::exp(-geometry - std::abs(lp_o - luminance(other.value[q])) * inv_o);
            }
            sum_d += wd * diffuse.value[q];
            sum_o += wo * other.value[q];
            weight_d += wd, weight_o += wo;
            var_d += wd * wd * diffuse.variance[q];
            var_o += wo * wo * other.variance[q];
          }
        }
        next_diffuse.value[p] = sum_d / weight_d;
        next_other.value[p] = sum_o / weight_o;
        next_diffuse.variance[p] = var_d / (weight_d * weight_d);
        next_other.variance[p] = var_o / (weight_o * weight_o);
      }
    });
    std::swap(diffuse, next_diffuse);
    std::swap(other, next_other);
  }

  std::vector<Color> out(n);
  for (std::size_t i = 0; i < n; ++i)
    out[i] = diffuse.value[i].cwiseProduct(film.albedo[i].cwiseMax(kAlbedoFloor)) + other.value[i];
  return out;
}

}  // namespace wobble::render
