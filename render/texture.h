// Texture: a colour as a function of surface UV (v up, OBJ convention), in linear RGB.
//
// Procedural textures, no parameters beyond their colours and scale:
//   ConstantTexture(color)
//   CheckerTexture(a, b, squares)  squares per unit of UV along u and v; square (0, 0) has colour a. Filtered in closed
//                                  form over the footprint's bounding box (pbrt's box-filtered checkerboard).
//   WoodTexture(light, dark, rings, planks)  a plank floor: `planks` boards per unit of v, running along u, with
//                                    dark joints between them; `rings` grain lines across each board (5 to 15), bent
//                                    and offset per board, with a slightly different tone per board. Filtered in
//                                    closed form over the footprint's bounding box: joints by the share of the box they
//                                    cover, each wave of the grain by its box-filtered amplitude (sinc), the late-wood
//                                    band and the board tones fading to their means as the box spans them.
// The image texture is in image_texture.h.
//
// Filtering: evalFootprint averages the texture over a pixel's footprint in UV space (the parallelogram spanned by
// the UV derivatives duv/dx and duv/dy, from ray differentials, path_tracer.h) with a kx x ky grid of lookups, k
// each edge's length over the texture's finest feature (featureSize(), in UV units), at most kMaxLookups. So a far-away
// wooden floor is not a field of speckles at one sample per pixel: its joints and grain average out as they would over
// the pixel. The grid is offset by `jitter` (in [0, 1)^2, the sample's pixel jitter), which keeps it unbiased.
#pragma once
#include <limits>

#include <Eigen/Core>

#include "render/color.h"

namespace wobble::render {

struct TextureFootprint {
  Eigen::Vector2f duvdx = Eigen::Vector2f::Zero(), duvdy = Eigen::Vector2f::Zero();
  Eigen::Vector2f jitter = Eigen::Vector2f::Constant(0.5f);
};

class Texture {
 public:
  virtual ~Texture() = default;
  virtual Color eval(const Eigen::Vector2f& uv) const = 0;
  // The smallest detail worth resolving, in UV units; infinite for a constant.
  virtual float featureSize() const = 0;
  static constexpr int kMaxLookups = 4;
  // By default the grid of lookups above; procedural textures override it with their own closed-form filter.
  virtual Color evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& footprint) const;
};

class ConstantTexture final : public Texture {
 public:
  explicit ConstantTexture(const Color& color) : color_(color) {}
  Color eval(const Eigen::Vector2f&) const override { return color_; }
  float featureSize() const override { return std::numeric_limits<float>::infinity(); }

 private:
  Color color_;
};

class CheckerTexture final : public Texture {
 public:
  CheckerTexture(const Color& a, const Color& b, float squares) : a_(a), b_(b), squares_(squares) {}
  Color eval(const Eigen::Vector2f& uv) const override;
  float featureSize() const override { return 0.5f / squares_; }
  Color evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& footprint) const override;

 private:
  Color a_, b_;
  float squares_;
};

class WoodTexture final : public Texture {
 public:
  WoodTexture(const Color& light = {0.60f, 0.38f, 0.20f}, const Color& dark = {0.28f, 0.14f, 0.06f}, float rings = 8,
              float planks = 4)
      : light_(light), dark_(dark), rings_(rings), planks_(planks) {}
  Color eval(const Eigen::Vector2f& uv) const override { return shade(uv, 0, 0); }
  float featureSize() const override;  // the fibre's period across a board
  Color evalFootprint(const Eigen::Vector2f& uv, const TextureFootprint& footprint) const override;

 private:
  // Box-filtered over fu along u and fw across the boards (in boards); 0, 0 is a point sample.
  Color shade(const Eigen::Vector2f& uv, float fu, float fw) const;
  // One board (index plank) over [across - fw/2, across + fw/2] (within it) by fu along u.
  Color board(long plank, float u, float across, float fw, float fu) const;
  // Over many boards [a, b]: each board's mean grain and tone, the joints by their share.
  Color meanColor(float a, float b, float u, float fu) const;
  static constexpr long kMaxBoards = 4;

  Color light_, dark_;
  float rings_, planks_;
};

}  // namespace wobble::render
