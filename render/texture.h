// Texture: a colour as a function of surface UV (v up, OBJ convention), in linear RGB.
//
// Procedural textures, no parameters beyond their colours and scale:
//   ConstantTexture(color)
//   CheckerTexture(a, b, squares)  squares per unit of UV along u and v; square (0, 0) has colour a
//   WoodTexture(light, dark, rings, planks)  a plank floor: `planks` boards per unit of v, running along u, with
//                                    dark joints between them; `rings` grain lines across each board (5 to 15), bent
//                                    and offset per board, with a slightly different tone per board
// The image texture is in image_texture.h.
#pragma once
#include <Eigen/Core>

#include "color.h"

namespace wobble::render {

class Texture {
 public:
  virtual ~Texture() = default;
  virtual Color eval(const Eigen::Vector2f& uv) const = 0;
};

class ConstantTexture final : public Texture {
 public:
  explicit ConstantTexture(const Color& color) : color_(color) {}
  Color eval(const Eigen::Vector2f&) const override { return color_; }

 private:
  Color color_;
};

class CheckerTexture final : public Texture {
 public:
  CheckerTexture(const Color& a, const Color& b, float squares) : a_(a), b_(b), squares_(squares) {}
  Color eval(const Eigen::Vector2f& uv) const override;

 private:
  Color a_, b_;
  float squares_;
};

class WoodTexture final : public Texture {
 public:
  WoodTexture(const Color& light = {0.60f, 0.38f, 0.20f}, const Color& dark = {0.28f, 0.14f, 0.06f},
              float rings = 8, float planks = 4)
      : light_(light), dark_(dark), rings_(rings), planks_(planks) {}
  Color eval(const Eigen::Vector2f& uv) const override;

 private:
  Color light_, dark_;
  float rings_, planks_;
};

}  // namespace wobble::render
