// Jelly and cloth builders: exact spring counts by type, rest lengths, pins, and the surface meshes.
#include <gtest/gtest.h>

#include "sim/bodies/cloth.h"
#include "sim/bodies/jelly.h"

namespace wobble {
namespace {

// Counted independently of the builder: pairs of lattice points per offset class.
TEST(Jelly, SpringCountsMatchLatticeFormulas) {
  for (int n : {2, 3, 5, 10}) {
    const Body j = buildJelly("j", {.n = n});
    const std::size_t m = n - 1;
    const std::size_t structural = 3 * n * n * m;
    const std::size_t shear = 6 * n * m * m + 4 * m * m * m;  // face diagonals + body diagonals
    const std::size_t bending = 3 * n * n * std::max(n - 2, 0);
    EXPECT_EQ(j.springs.count(SpringType::Structural), structural) << "n = " << n;
    EXPECT_EQ(j.springs.count(SpringType::Shear), shear) << "n = " << n;
    EXPECT_EQ(j.springs.count(SpringType::Bending), bending) << "n = " << n;
    EXPECT_EQ(j.particleCount(), n * n * n);
  }
  EXPECT_EQ(buildJelly("j", {}).springs.size(), 2700u + 7776u + 2400u);  // the default 10^3 jelly
}

TEST(Jelly, RestLengthsAreInitialDistancesAndTypesHaveTheirLengths) {
  const Body j = buildJelly("j", {.n = 4, .size = 3, .rotation_deg = 33});
  const double h = 1.0;  // size 3 over 3 intervals
  for (std::size_t s = 0; s < j.springs.size(); ++s) {
    const double len = (particle(j.x, j.springs.a[s]) - particle(j.x, j.springs.b[s])).norm();
    EXPECT_NEAR(j.springs.rest[s], len, 1e-12);
    switch (j.springs.type[s]) {
      case SpringType::Structural:
        EXPECT_NEAR(len, h, 1e-12);
        break;
      case SpringType::Bending:
        EXPECT_NEAR(len, 2 * h, 1e-12);
        break;
      case SpringType::Shear:
        EXPECT_TRUE(std::abs(len - std::sqrt(2.0)) < 1e-12 || std::abs(len - std::sqrt(3.0)) < 1e-12);
    }
  }
}

TEST(Jelly, DefaultPlacementMatchesCourseFramework) {
  const Body j = buildJelly("j", {});
  double lowest = 1e9;
  for (int i = 0; i < j.particleCount(); ++i) lowest = std::min(lowest, particle(j.x, i).y());
  EXPECT_NEAR(lowest, 6.78, 1e-9);
  EXPECT_EQ(j.mass.sum(), 1000.0);
}

TEST(Jelly, SurfaceIsSixOutwardTexturedFaces) {
  const int n = 5;
  const Body j = buildJelly("j", {.n = n, .rotation_deg = 20});
  const SurfaceMesh& s = j.surface;
  EXPECT_EQ(s.vertexCount(), 6u * n * n);
  EXPECT_EQ(s.triangles.size(), 12u * (n - 1) * (n - 1));
  const Vec3 centre = j.x.reshaped(3, j.particleCount()).rowwise().mean();
  for (const auto& t : s.triangles) {
    const Vec3 a = particle(j.x, s.particle[t[0]]), b = particle(j.x, s.particle[t[1]]),
               c = particle(j.x, s.particle[t[2]]);
    EXPECT_GT((b - a).cross(c - a).dot((a + b + c) / 3 - centre), 0) << "triangle faces inward";
  }
  for (const auto& uv : s.uv) EXPECT_TRUE(uv.x() >= 0 && uv.x() <= 1 && uv.y() >= 0 && uv.y() <= 1);
  // Each face's texture is upright on the side faces: v grows with height.
  const Body upright = buildJelly("j", {.n = n});
  for (int face = 0; face < 4; ++face) {
    const int bottom = face * n * n, top = bottom + n * (n - 1);
    EXPECT_GT(particle(upright.x, upright.surface.particle[top]).y(),
              particle(upright.x, upright.surface.particle[bottom]).y());
    EXPECT_EQ(upright.surface.uv[top].y(), 1.0f);
  }
}

TEST(Surface, NormalsPointOutOfTheJelly) {
  const Body j = buildJelly("j", {.n = 4});
  const SurfaceFrame f = evaluateSurface(j.surface, j.x, 0);
  const Vec3 centre = j.x.reshaped(3, j.particleCount()).rowwise().mean();
  for (std::size_t i = 0; i < f.positions.size(); ++i) {
    EXPECT_NEAR(f.normals[i].norm(), 1.0f, 1e-6);
    EXPECT_GT(f.normals[i].cast<double>().dot(f.positions[i].cast<double>() - centre), 0);
  }
}

TEST(Cloth, SpringCountsPinsAndSurface) {
  const int nx = 6, ny = 4;
  ClothParams p{.nx = nx, .ny = ny};
  p.pinned = clothPinSet("corners", nx, ny);
  const Body c = buildCloth("c", p);
  EXPECT_EQ(c.springs.count(SpringType::Structural), std::size_t((nx - 1) * ny + nx * (ny - 1)));
  EXPECT_EQ(c.springs.count(SpringType::Shear), std::size_t(2 * (nx - 1) * (ny - 1)));
  EXPECT_EQ(c.springs.count(SpringType::Bending), std::size_t((nx - 2) * ny + nx * (ny - 2)));
  EXPECT_EQ(std::count(c.pinned.begin(), c.pinned.end(), true), 4);
  for (int corner : {0, nx - 1, nx * (ny - 1), nx * ny - 1}) EXPECT_TRUE(c.pinned[corner]);
  EXPECT_EQ(c.surface.vertexCount(), std::size_t(nx * ny));
  EXPECT_EQ(c.surface.triangles.size(), std::size_t(2 * (nx - 1) * (ny - 1)));
  const SurfaceFrame f = evaluateSurface(c.surface, c.x, 0);
  for (const auto& normal : f.normals) EXPECT_NEAR(normal.y(), 1.0f, 1e-6);  // horizontal cloth faces up
  // Default cloth spans x, z in [-2, 2] at y = 1.
  const Body d = buildCloth("d", {});
  EXPECT_EQ(particle(d.x, 0), Vec3(-2, 1, -2));
  EXPECT_EQ(particle(d.x, 25 * 25 - 1), Vec3(2, 1, 2));
}

TEST(Cloth, NamedPinSets) {
  EXPECT_EQ(clothPinSet("top-edge", 3, 5), (std::vector<int>{0, 1, 2}));
  EXPECT_THROW(clothPinSet("middle", 3, 5), std::invalid_argument);
  ClothParams p{.nx = 3, .ny = 3, .hanging = true};
  p.pinned = clothPinSet("top-edge", 3, 3);
  const Body c = buildCloth("c", p);
  for (int i = 0; i < 3; ++i) EXPECT_GT(particle(c.x, i).y(), particle(c.x, i + 3).y());  // row 0 is the top
}

}  // namespace
}  // namespace wobble

namespace wobble {
namespace {

// The sizes the scene reader budgets before building (app/scene_limits.h) are exactly what the builders make.
TEST(BodySize, MatchesTheBuilders) {
  for (int n : {2, 3, 5}) {
    JellyParams p;
    p.n = n;
    const Body b = buildJelly("j", p);
    const BodySize s = jellySize(n);
    EXPECT_EQ(s.particles, b.particleCount());
    EXPECT_EQ(s.springs, std::int64_t(b.springs.size()));
    EXPECT_EQ(s.surface_vertices, std::int64_t(b.surface.vertexCount()));
    EXPECT_EQ(s.triangles, std::int64_t(b.surface.triangles.size()));
  }
  for (auto [nx, ny] : {std::pair{2, 2}, {5, 3}, {2, 7}}) {
    ClothParams p;
    p.nx = nx, p.ny = ny;
    const Body b = buildCloth("c", p);
    const BodySize s = clothSize(nx, ny);
    EXPECT_EQ(s.particles, b.particleCount());
    EXPECT_EQ(s.springs, std::int64_t(b.springs.size()));
    EXPECT_EQ(s.surface_vertices, std::int64_t(b.surface.vertexCount()));
    EXPECT_EQ(s.triangles, std::int64_t(b.surface.triangles.size()));
  }
  EXPECT_EQ(jellySize(2048).particles, std::int64_t{2048} * 2048 * 2048);  // 64-bit: no wrap
  EXPECT_EQ(clothSize(65536, 65536).particles, std::int64_t{1} << 32);
}

// More particles than 32-bit indices can address is refused by the builders themselves, before any allocation.
TEST(BodySize, BuildersRefuseTooManyParticles) {
  JellyParams j;
  j.n = 2048;
  EXPECT_THROW(buildJelly("j", j), std::length_error);
  ClothParams c;
  c.nx = c.ny = 65536;
  EXPECT_THROW(buildCloth("c", c), std::length_error);
}

}  // namespace
}  // namespace wobble
