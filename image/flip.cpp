// FLIP and HDR-FLIP (see flip.h).
#include "image/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>

namespace wobble::image {

namespace {

constexpr double kPi = 3.14159265358979323846;

using Vec3 = std::array<float, 3>;
using Mat3 = std::array<std::array<double, 3>, 3>;

// Linear sRGB (D65) -> CIE XYZ: the primaries of IEC 61966-2-1 in exact rational form.
constexpr Mat3 kRgbToXyz = {{{10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794},
                             {2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897},
                             {1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382}}};

Mat3 inverse(const Mat3& m) {
  Mat3 inv;
  const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                     m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                     m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      inv[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) / det;
    }
  return inv;
}

const Mat3& xyzToRgb() {
  static const Mat3 m = inverse(kRgbToXyz);
  return m;
}

Vec3 mul(const Mat3& m, const Vec3& v) {
  Vec3 out;
  for (int r = 0; r < 3; ++r) out[r] = float(m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2]);
  return out;
}

// The reference white: XYZ of linear RGB (1, 1, 1).
const Vec3& white() {
  static const Vec3 w = mul(kRgbToXyz, {1, 1, 1});
  return w;
}

float srgbToLinear(float v) { return v > 0.04045f ? std::pow((v + 0.055f) / 1.055f, 2.4f) : v / 12.92f; }
float linearToSrgb(float v) { return v > 0.0031308f ? 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f : 12.92f * v; }

// YyCxCz: the opponent space of the colour pipeline (linear in XYZ, unlike L*a*b*).
Vec3 xyzToYcxcz(const Vec3& xyz) {
  const Vec3& w = white();
  const float x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
  return {116 * y - 16, 500 * (x - y), 200 * (y - z)};
}

Vec3 ycxczToXyz(const Vec3& c) {
  const Vec3& w = white();
  const float y = (c[0] + 16) / 116;
  return {(y + c[1] / 500) * w[0], y * w[1], (y - c[2] / 200) * w[2]};
}

Vec3 xyzToLab(const Vec3& xyz) {
  constexpr float delta = 6.0f / 29;
  float f[3];
  for (int i = 0; i < 3; ++i) {
    const float t = xyz[i] / white()[i];
    f[i] = t > delta * delta * delta ? std::cbrt(t) : t / (3 * delta * delta) + 4.0f / 29;
  }
  return {116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])};
}

// Hunt-adjusted L*a*b* of a linear RGB colour: chroma scaled by 0.01 L*, as the eye sees less of it in the dark.
Vec3 huntLab(const Vec3& rgb) {
  Vec3 lab = xyzToLab(mul(kRgbToXyz, rgb));
  lab[1] *= 0.01f * lab[0];
  lab[2] *= 0.01f * lab[0];
  return lab;
}

float hyab(const Vec3& a, const Vec3& b) { return std::fabs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }

// One channel plane, width * height, row-major.
using Plane = std::vector<float>;

// Separable convolution, kernels indexed -r..r, borders extended by their edge pixels.
Plane convolve(const Plane& in, int w, int h, const std::vector<float>& kx, const std::vector<float>& ky) {
  const int rx = int(kx.size() / 2), ry = int(ky.size() / 2);
  Plane tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int i = -rx; i <= rx; ++i)
        s += kx[std::size_t(i + rx)] * in[std::size_t(y) * w + std::clamp(x + i, 0, w - 1)];
      tmp[std::size_t(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float s = 0;
      for (int j = -ry; j <= ry; ++j)
        s += ky[std::size_t(j + ry)] * tmp[std::size_t(std::clamp(y + j, 0, h - 1)) * w + x];
      out[std::size_t(y) * w + x] = s;
    }
  return out;
}

// The contrast sensitivity filter of one opponent channel: sum over k of a_k sqrt(pi / b_k) exp(-pi^2 r^2 / b_k)
// (r in degrees), normalised to sum 1 over its square support. Each term is separable; the channel is filtered by
// each and the results added with the term's share.
struct CsfTerm {
  double a, b;
};
constexpr CsfTerm kAchromatic[] = {{1, 0.0047}};
constexpr CsfTerm kRedGreen[] = {{1, 0.0053}};
constexpr CsfTerm kBlueYellow[] = {{34.1, 0.04}, {13.5, 0.025}};

Plane csfFilter(const Plane& in, int w, int h, std::span<const CsfTerm> terms, double ppd) {
  constexpr double kWidestB = 0.04;  // the support is the same for all three channels, set by the widest Gaussian
  const int r = int(std::ceil(3 * std::sqrt(kWidestB / (2 * kPi * kPi)) * ppd));
  const double dx = 1.0 / ppd;
  std::vector<std::vector<float>> g;
  std::vector<double> weight;
  double total = 0;
  for (const CsfTerm& t : terms) {
    std::vector<float>& k = g.emplace_back(2 * std::size_t(r) + 1);
    double sum = 0;
    for (int i = -r; i <= r; ++i)
      sum += k[std::size_t(i + r)] = float(std::exp(-kPi * kPi * (i * dx) * (i * dx) / t.b));
    weight.push_back(t.a * std::sqrt(kPi / t.b));
    total += weight.back() * sum * sum;
  }
  Plane out(in.size(), 0.0f);
  for (std::size_t k = 0; k < g.size(); ++k) {
    const Plane part = convolve(in, w, h, g[k], g[k]);
    const float share = float(weight[k] / total);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] += share * part[i];
  }
  return out;
}

// Edge (first derivative) or point (second derivative) detector along x, and the Gaussian across: positive weights
// normalised to sum 1 and negative ones to -1, as the paper does with the 2-D kernel (the Gaussian factor, positive,
// carries its share to both).
struct FeatureKernels {
  std::vector<float> edge, point, gauss;
};

FeatureKernels featureKernels(double ppd) {
  constexpr double kW = 0.082;  // degrees between the two standard deviations of the eye's edge detector
  const double sd = 0.5 * kW * ppd;
  const int r = int(std::ceil(3 * sd));
  FeatureKernels k;
  double gsum = 0;
  for (int i = -r; i <= r; ++i) {
    const double g = std::exp(-(i * i) / (2 * sd * sd));
    k.gauss.push_back(float(g));
    k.edge.push_back(float(-i * g));
    k.point.push_back(float((i * i / (sd * sd) - 1) * g));
    gsum += g;
  }
  for (float& v : k.gauss) v = float(v / gsum);
  for (std::vector<float>* d : {&k.edge, &k.point}) {
    double pos = 0, neg = 0;
    for (float v : *d) (v > 0 ? pos : neg) += v;
    for (float& v : *d) v = float(v > 0 ? v / pos : v < 0 ? v / -neg : 0);
  }
  return k;
}

// The magnitudes of the edge and point responses of a luminance plane.
std::pair<Plane, Plane> features(const Plane& y, int w, int h, const FeatureKernels& k) {
  const Plane ex = convolve(y, w, h, k.edge, k.gauss), ey = convolve(y, w, h, k.gauss, k.edge);
  const Plane px = convolve(y, w, h, k.point, k.gauss), py = convolve(y, w, h, k.gauss, k.point);
  Plane edges(y.size()), points(y.size());
  for (std::size_t i = 0; i < y.size(); ++i) {
    edges[i] = std::hypot(ex[i], ey[i]);
    points[i] = std::hypot(px[i], py[i]);
  }
  return {edges, points};
}

Vec3 rgbAt(const ImageF& image, std::size_t i) {
  const float* p = image.pixels.data() + i * std::size_t(image.channels);
  return image.channels >= 3 ? Vec3{p[0], p[1], p[2]} : Vec3{p[0], p[0], p[0]};
}

void checkSameSize(const ImageF& a, const ImageF& b) {
  if (a.width != b.width || a.height != b.height || a.width <= 0 || a.height <= 0)
    throw std::invalid_argument("FLIP compares images of the same size: " + std::to_string(a.width) + " x " +
                                std::to_string(a.height) + " against " + std::to_string(b.width) + " x " +
                                std::to_string(b.height));
}

// LDR-FLIP of two images of sRGB-encoded colours (3 channels, values in [0, 1]).
ImageF ldrFlipRgb(const ImageF& reference, const ImageF& test, double ppd) {
  const int w = reference.width, h = reference.height;
  const std::size_t n = std::size_t(w) * h;
  constexpr float kQc = 0.7f, kQf = 0.5f, kPc = 0.4f, kPt = 0.95f;

  // Opponent planes (Yy, Cx, Cz) and the normalised luminance of both images.
  std::array<std::array<Plane, 3>, 2> opp;
  std::array<Plane, 2> lum;
  for (int k = 0; k < 2; ++k) {
    const ImageF& img = k == 0 ? reference : test;
    for (auto& p : opp[k]) p.resize(n);
    lum[k].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 rgb = rgbAt(img, i);
      for (float& v : rgb) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
      const Vec3 c = xyzToYcxcz(mul(kRgbToXyz, rgb));
      for (int ch = 0; ch < 3; ++ch) opp[k][std::size_t(ch)][i] = c[std::size_t(ch)];
      lum[k][i] = (c[0] + 16) / 116;
    }
  }
  // Colour pipeline.
  std::array<std::vector<Vec3>, 2> lab;
  for (int k = 0; k < 2; ++k) {
    const Plane a = csfFilter(opp[k][0], w, h, kAchromatic, ppd);
    const Plane rg = csfFilter(opp[k][1], w, h, kRedGreen, ppd);
    const Plane by = csfFilter(opp[k][2], w, h, kBlueYellow, ppd);
    lab[k].resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 rgb = mul(xyzToRgb(), ycxczToXyz({a[i], rg[i], by[i]}));
      for (float& v : rgb) v = std::clamp(v, 0.0f, 1.0f);
      lab[k][i] = huntLab(rgb);
    }
  }
  static const float cmax = std::pow(hyab(huntLab({0, 1, 0}), huntLab({0, 0, 1})), kQc);
  const float pccmax = kPc * cmax;
  // Feature pipeline.
  const FeatureKernels kernels = featureKernels(ppd);
  const auto [edges_r, points_r] = features(lum[0], w, h, kernels);
  const auto [edges_t, points_t] = features(lum[1], w, h, kernels);

  ImageF out(w, h, 1);
  for (std::size_t i = 0; i < n; ++i) {
    const float e = std::pow(hyab(lab[0][i], lab[1][i]), kQc);
    const float color = e < pccmax ? kPt / pccmax * e : kPt + (e - pccmax) / (cmax - pccmax) * (1 - kPt);
    const float d = std::max(std::fabs(edges_r[i] - edges_t[i]), std::fabs(points_t[i] - points_r[i]));
    const float feature = std::pow(d / std::sqrt(2.0f), kQf);
    out.pixels[i] = std::clamp(std::pow(color, 1 - feature), 0.0f, 1.0f);
  }
  return out;
}

// The ACES filmic fit (Narkowicz 2016) with its 0.6 pre-exposure folded into the constants, as HDR-FLIP uses it.
constexpr double kAces[6] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

float acesToneMap(float x) {
  if (!(x > 0)) return 0;  // negative and NaN values: black
  if (std::isinf(x)) return 1;
  const double y = (kAces[0] * x * x + kAces[1] * x + kAces[2]) / (kAces[3] * x * x + kAces[4] * x + kAces[5]);
  return float(std::clamp(y, 0.0, 1.0));
}

// The input that the tone curve maps to t.
double acesInverse(double t) {
  const double c0 = (kAces[1] - kAces[4] * t) / (kAces[0] - kAces[3] * t);
  const double c1 = (kAces[2] - kAces[5] * t) / (kAces[0] - kAces[3] * t);
  return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

}  // namespace

ImageF ldrFlip(const ImageF& reference, const ImageF& test, double ppd) {
  checkSameSize(reference, test);
  return ldrFlipRgb(reference, test, ppd);
}

FlipExposures hdrFlipExposures(const ImageF& reference) {
  std::vector<float> y;
  y.reserve(std::size_t(reference.width) * reference.height);
  for (std::size_t i = 0; i < std::size_t(reference.width) * reference.height; ++i) {
    const Vec3 c = rgbAt(reference, i);
    const float l = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
    y.push_back(std::isfinite(l) ? std::max(l, 0.0f) : 0.0f);
  }
  FlipExposures e;
  if (y.empty()) return e;
  const float y_hi = *std::max_element(y.begin(), y.end());
  if (y_hi <= 0) return e;  // an all-black reference: one exposure is as good as any
  const double x = acesInverse(0.85);
  e.start = std::log2(x / y_hi);
  std::sort(y.begin(), y.end());
  const double rank = 0.5 * double(y.size() - 1);  // the median, interpolated as numpy's percentile
  const std::size_t lo = std::size_t(rank);
  double y_lo = y[lo] + (rank - double(lo)) * (y[std::min(lo + 1, y.size() - 1)] - y[lo]);
  if (y_lo <= 0) y_lo = *std::upper_bound(y.begin(), y.end(), 0.0f);  // a mostly black reference: its dimmest light
  e.stop = std::log2(x / y_lo);
  constexpr int kMaxExposures = 40;  // bounds the time on images with a huge range; 40 stops is 1e12
  e.count = std::clamp(int(std::ceil(e.stop - e.start)), 2, kMaxExposures);
  return e;
}

ImageF hdrFlip(const ImageF& reference, const ImageF& test, double ppd) {
  checkSameSize(reference, test);
  const FlipExposures e = hdrFlipExposures(reference);
  const double step = (e.stop - e.start) / std::max(e.count - 1, 1);
  ImageF result(reference.width, reference.height, 1);
  const std::size_t n = result.pixels.size();
  for (int k = 0; k < e.count; ++k) {
    const float scale = float(std::exp2(e.start + k * step));
    ImageF ldr[2] = {ImageF(reference.width, reference.height, 3), ImageF(reference.width, reference.height, 3)};
    for (int j = 0; j < 2; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3 c = rgbAt(j == 0 ? reference : test, i);
        for (int ch = 0; ch < 3; ++ch)
          ldr[j].pixels[3 * i + std::size_t(ch)] = linearToSrgb(acesToneMap(scale * c[std::size_t(ch)]));
      }
    const ImageF error = ldrFlipRgb(ldr[0], ldr[1], ppd);
    for (std::size_t i = 0; i < n; ++i) result.pixels[i] = std::max(result.pixels[i], error.pixels[i]);
  }
  return result;
}

double flipPercentile(const ImageF& error_map, double q) {
  std::vector<float> v = error_map.pixels;
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double rank = std::clamp(q, 0.0, 100.0) / 100.0 * double(v.size() - 1);
  const std::size_t lo = std::size_t(rank);
  return v[lo] + (rank - double(lo)) * (v[std::min(lo + 1, v.size() - 1)] - v[lo]);
}

FlipStats flipStats(const ImageF& error_map) {
  FlipStats s;
  std::vector<float> v = error_map.pixels;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  const double sum = std::accumulate(v.begin(), v.end(), 0.0);
  s.mean = sum / double(v.size());
  s.min = v.front();
  s.max = v.back();
  // Weighted percentile: the error where the running sum of the sorted errors reaches that share of their total
  // (the FLIP tool's pooling; between the two values around it).
  std::vector<double> cumulative(v.size());
  std::partial_sum(v.begin(), v.end(), cumulative.begin(), [](double a, float b) { return a + b; });
  const auto weighted = [&](double share) {
    const std::size_t i =
        std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), sum * share) - cumulative.begin());
    const std::size_t a = std::min(i, v.size() - 1), b = std::min(i + 1, v.size() - 1);
    return 0.5 * (double(v[a]) + double(v[b]));
  };
  s.weighted_median = weighted(0.5);
  s.weighted_q1 = weighted(0.25);
  s.weighted_q3 = weighted(0.75);
  s.p50 = flipPercentile(error_map, 50);
  s.p95 = flipPercentile(error_map, 95);
  s.p99 = flipPercentile(error_map, 99);
  return s;
}

Image8 magmaHeatmap(const ImageF& error_map) {
  // matplotlib's magma (Smith and van der Walt, CC0), 256 entries as 8-bit sRGB codes.
  static constexpr std::uint8_t kMagma[256][3] = {
      {0, 0, 4},       {1, 0, 5},       {1, 1, 6},       {1, 1, 8},       {2, 1, 9},       {2, 2, 11},
      {2, 2, 13},      {3, 3, 15},      {3, 3, 18},      {4, 4, 20},      {5, 4, 22},      {6, 5, 24},
      {6, 5, 26},      {7, 6, 28},      {8, 7, 30},      {9, 7, 32},      {10, 8, 34},     {11, 9, 36},
      {12, 9, 38},     {13, 10, 41},    {14, 11, 43},    {16, 11, 45},    {17, 12, 47},    {18, 13, 49},
      {19, 13, 52},    {20, 14, 54},    {21, 14, 56},    {22, 15, 59},    {24, 15, 61},    {25, 16, 63},
      {26, 16, 66},    {28, 16, 68},    {29, 17, 71},    {30, 17, 73},    {32, 17, 75},    {33, 17, 78},
      {34, 17, 80},    {36, 18, 83},    {37, 18, 85},    {39, 18, 88},    {41, 17, 90},    {42, 17, 92},
      {44, 17, 95},    {45, 17, 97},    {47, 17, 99},    {49, 17, 101},   {51, 16, 103},   {52, 16, 105},
      {54, 16, 107},   {56, 16, 108},   {57, 15, 110},   {59, 15, 112},   {61, 15, 113},   {63, 15, 114},
      {64, 15, 116},   {66, 15, 117},   {68, 15, 118},   {69, 16, 119},   {71, 16, 120},   {73, 16, 120},
      {74, 16, 121},   {76, 17, 122},   {78, 17, 123},   {79, 18, 123},   {81, 18, 124},   {82, 19, 124},
      {84, 19, 125},   {86, 20, 125},   {87, 21, 126},   {89, 21, 126},   {90, 22, 126},   {92, 22, 127},
      {93, 23, 127},   {95, 24, 127},   {96, 24, 128},   {98, 25, 128},   {100, 26, 128},  {101, 26, 128},
      {103, 27, 128},  {104, 28, 129},  {106, 28, 129},  {107, 29, 129},  {109, 29, 129},  {110, 30, 129},
      {112, 31, 129},  {114, 31, 129},  {115, 32, 129},  {117, 33, 129},  {118, 33, 129},  {120, 34, 129},
      {121, 34, 130},  {123, 35, 130},  {124, 35, 130},  {126, 36, 130},  {128, 37, 130},  {129, 37, 129},
      {131, 38, 129},  {132, 38, 129},  {134, 39, 129},  {136, 39, 129},  {137, 40, 129},  {139, 41, 129},
      {140, 41, 129},  {142, 42, 129},  {144, 42, 129},  {145, 43, 129},  {147, 43, 128},  {148, 44, 128},
      {150, 44, 128},  {152, 45, 128},  {153, 45, 128},  {155, 46, 127},  {156, 46, 127},  {158, 47, 127},
      {160, 47, 127},  {161, 48, 126},  {163, 48, 126},  {165, 49, 126},  {166, 49, 125},  {168, 50, 125},
      {170, 51, 125},  {171, 51, 124},  {173, 52, 124},  {174, 52, 123},  {176, 53, 123},  {178, 53, 123},
      {179, 54, 122},  {181, 54, 122},  {183, 55, 121},  {184, 55, 121},  {186, 56, 120},  {188, 57, 120},
      {189, 57, 119},  {191, 58, 119},  {192, 58, 118},  {194, 59, 117},  {196, 60, 117},  {197, 60, 116},
      {199, 61, 115},  {200, 62, 115},  {202, 62, 114},  {204, 63, 113},  {205, 64, 113},  {207, 64, 112},
      {208, 65, 111},  {210, 66, 111},  {211, 67, 110},  {213, 68, 109},  {214, 69, 108},  {216, 69, 108},
      {217, 70, 107},  {219, 71, 106},  {220, 72, 105},  {222, 73, 104},  {223, 74, 104},  {224, 76, 103},
      {226, 77, 102},  {227, 78, 101},  {228, 79, 100},  {229, 80, 100},  {231, 82, 99},   {232, 83, 98},
      {233, 84, 98},   {234, 86, 97},   {235, 87, 96},   {236, 88, 96},   {237, 90, 95},   {238, 91, 94},
      {239, 93, 94},   {240, 95, 94},   {241, 96, 93},   {242, 98, 93},   {242, 100, 92},  {243, 101, 92},
      {244, 103, 92},  {244, 105, 92},  {245, 107, 92},  {246, 108, 92},  {246, 110, 92},  {247, 112, 92},
      {247, 114, 92},  {248, 116, 92},  {248, 118, 92},  {249, 120, 93},  {249, 121, 93},  {249, 123, 93},
      {250, 125, 94},  {250, 127, 94},  {250, 129, 95},  {251, 131, 95},  {251, 133, 96},  {251, 135, 97},
      {252, 137, 97},  {252, 138, 98},  {252, 140, 99},  {252, 142, 100}, {252, 144, 101}, {253, 146, 102},
      {253, 148, 103}, {253, 150, 104}, {253, 152, 105}, {253, 154, 106}, {253, 155, 107}, {254, 157, 108},
      {254, 159, 109}, {254, 161, 110}, {254, 163, 111}, {254, 165, 113}, {254, 167, 114}, {254, 169, 115},
      {254, 170, 116}, {254, 172, 118}, {254, 174, 119}, {254, 176, 120}, {254, 178, 122}, {254, 180, 123},
      {254, 182, 124}, {254, 183, 126}, {254, 185, 127}, {254, 187, 129}, {254, 189, 130}, {254, 191, 132},
      {254, 193, 133}, {254, 194, 135}, {254, 196, 136}, {254, 198, 138}, {254, 200, 140}, {254, 202, 141},
      {254, 204, 143}, {254, 205, 144}, {254, 207, 146}, {254, 209, 148}, {254, 211, 149}, {254, 213, 151},
      {254, 215, 153}, {254, 216, 154}, {253, 218, 156}, {253, 220, 158}, {253, 222, 160}, {253, 224, 161},
      {253, 226, 163}, {253, 227, 165}, {253, 229, 167}, {253, 231, 169}, {253, 233, 170}, {253, 235, 172},
      {252, 236, 174}, {252, 238, 176}, {252, 240, 178}, {252, 242, 180}, {252, 244, 182}, {252, 246, 184},
      {252, 247, 185}, {252, 249, 187}, {252, 251, 189}, {252, 253, 191},
  };
  Image8 out(error_map.width, error_map.height, 3);
  for (std::size_t i = 0; i < error_map.pixels.size(); ++i) {
    const float e = error_map.pixels[i];
    const int index = std::isfinite(e) ? int(std::lround(std::clamp(e, 0.0f, 1.0f) * 255)) : 255;
    for (int c = 0; c < 3; ++c) out.pixels[3 * i + std::size_t(c)] = kMagma[index][c];
  }
  return out;
}

}  // namespace wobble::image
