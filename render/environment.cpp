// The equirectangular environment map and its luminance sampling (environment.h).
#include "render/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "image/image_file.h"
#include "render/sampling.h"

namespace wobble::render {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

std::string describe(const std::filesystem::path& file) { return file.empty() ? "environment map" : file.string(); }

}  // namespace

EnvironmentMap::EnvironmentMap(const image::ImageF& rgb, float rotation_deg, float strength, std::filesystem::path file)
    : width_(rgb.width), height_(rgb.height), rotation_deg_(rotation_deg), strength_(strength), file_(std::move(file)) {
  const std::string name = describe(file_);
  if (rgb.height < 1 || rgb.width != 2 * rgb.height)
    throw std::invalid_argument(name + ": an equirectangular map is twice as wide as high; this one is " +
                                std::to_string(rgb.width) + " x " + std::to_string(rgb.height) + " pixels");
  if (rgb.channels != 1 && rgb.channels != 3)
    throw std::invalid_argument(name + ": needs 1 (grey) or 3 (RGB) channels, not " + std::to_string(rgb.channels));
  if (!std::isfinite(strength) || strength < 0)
    throw std::invalid_argument(name + ": the strength must be finite and >= 0, not " + std::to_string(strength));
  if (!std::isfinite(rotation_deg)) throw std::invalid_argument(name + ": the rotation must be finite");
  const float angle = rotation_deg * kPi / 180.0f;
  cos_rotation_ = std::cos(angle);
  sin_rotation_ = std::sin(angle);

  cos_theta_.resize(height_ + 1);
  for (int r = 0; r <= height_; ++r) cos_theta_[r] = std::cos(kPi * float(r) / float(height_));
  cos_theta_.front() = 1.0f, cos_theta_.back() = -1.0f;

  radiance_.resize(std::size_t(width_) * height_);
  std::vector<float> weight(radiance_.size());
  for (int y = 0; y < height_; ++y) {
    const float solid_angle = texelSolidAngle(y);
    for (int x = 0; x < width_; ++x) {
      Color c;
      for (int k = 0; k < 3; ++k) {
        const float v = rgb.at(x, y, rgb.channels == 1 ? 0 : k);
        if (!std::isfinite(v))
          throw std::invalid_argument(name + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                      ") is not a finite number");
        c[k] = std::max(0.0f, v);
      }
      const std::size_t i = std::size_t(y) * width_ + x;
      radiance_[i] = strength * c;
      weight[i] = luminance(c) * solid_angle;
      total_ += double(weight[i]);
    }
  }
  distribution_ = PiecewiseConstant2D(weight, width_, height_);
}

EnvironmentMap EnvironmentMap::load(const std::filesystem::path& file, float rotation_deg, float strength) {
  const image::ImageFile f = image::readImageFile(file);
  if (!f.linear)
    throw std::invalid_argument(file.string() + ": a " + f.format +
                                " image holds display values; an environment map must be linear radiance: a Radiance "
                                ".hdr or OpenEXR .exr file");
  const auto& c = f.channels;
  if (c.size() >= 3 && c[0] == "R" && c[1] == "G" && c[2] == "B") {
    if (c.size() == 3) return EnvironmentMap(f.image, rotation_deg, strength, file);
    image::ImageF rgb(f.image.width, f.image.height, 3);
    for (int y = 0; y < rgb.height; ++y)
      for (int x = 0; x < rgb.width; ++x)
        for (int k = 0; k < 3; ++k) rgb.at(x, y, k) = f.image.at(x, y, k);
    return EnvironmentMap(rgb, rotation_deg, strength, file);
  }
  if (!c.empty() && c[0] == "Y") {
    image::ImageF grey(f.image.width, f.image.height, 1);
    for (int y = 0; y < grey.height; ++y)
      for (int x = 0; x < grey.width; ++x) grey.at(x, y) = f.image.at(x, y);
    return EnvironmentMap(grey, rotation_deg, strength, file);
  }
  throw std::invalid_argument(file.string() + ": no R, G, B or Y channels to read radiance from");
}

float EnvironmentMap::texelSolidAngle(int row) const {
  return 2.0f * kPi / float(width_) * (cos_theta_[row] - cos_theta_[row + 1]);
}

int EnvironmentMap::texel(const Eigen::Vector3f& d) const {
  // Into the map's own frame: turned back by the rotation about +Y.
  const float x = cos_rotation_ * d.x() - sin_rotation_ * d.z(), z = sin_rotation_ * d.x() + cos_rotation_ * d.z();
  const float u = 0.5f + std::atan2(z, x) / (2.0f * kPi);
  const float v = std::acos(std::clamp(d.y(), -1.0f, 1.0f)) / kPi;
  const int column = std::clamp(int(u * float(width_)), 0, width_ - 1);
  const int row = std::clamp(int(v * float(height_)), 0, height_ - 1);
  return row * width_ + column;
}

Color EnvironmentMap::eval(const Eigen::Vector3f& d) const { return radiance_[texel(d)]; }

Eigen::Vector3f EnvironmentMap::sample(float u1, float u2, float& pdf) const {
  if (empty()) {
    pdf = 0;
    return Eigen::Vector3f::UnitY();
  }
  int column = 0, row = 0;
  float fx = 0, fy = 0;
  distribution_.sample(u1, u2, column, row, fx, fy);
  pdf = distribution_.probability(column, row) / texelSolidAngle(row);
  // Uniform over the texel's patch: linear in azimuth and in cos theta.
  const float cos_theta = cos_theta_[row] + fy * (cos_theta_[row + 1] - cos_theta_[row]);
  const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  // Azimuth 2 pi u - pi = 2 pi (u - 1/2): cosSin2Pi gives (cos, sin) of it from the turn u - 1/2.
  const Eigen::Vector2f phi = cosSin2Pi((float(column) + fx) / float(width_) - 0.5f);
  const float x = sin_theta * phi.x(), z = sin_theta * phi.y();
  // Out of the map's frame: turned by the rotation about +Y.
  return {cos_rotation_ * x + sin_rotation_ * z, cos_theta, -sin_rotation_ * x + cos_rotation_ * z};
}

float EnvironmentMap::pdf(const Eigen::Vector3f& d) const {
  if (empty()) return 0;
  const int i = texel(d), row = i / width_;
  return distribution_.probability(i % width_, row) / texelSolidAngle(row);
}

}  // namespace wobble::render
