// Renderer benchmarks, all on one scene: the simulator's 10 x 10 x 10 jelly lattice surface (600 vertices, 972
// triangles) resting on a 20 m quad, next to an analytic sphere, lit by a sun and the sky.
//   BM_EmbreeIntersect1   raw Embree: rtcIntersect1 on the scene's RTCScene, one thread, camera rays of a 1280x720
//                         view (first hits only, no shading): the ceiling for everything else
//   BM_EmbreePathRays     raw Embree on the renderer's kind of rays: camera, cosine bounce and sun shadow rays of
//                         BM_RendererRays' frame, made beforehand, replayed with rtcIntersect1 / rtcOccluded1
//   BM_EmbreePathRaysChained
//                         those rays' intersections alone: independent (argument 0) or each waiting for the hit
//                         before it (1)
//   BM_RendererRays       the renderer's rays per second (camera, bounce and shadow rays, with shading, texture
//                         lookups and sampling) on a 320x180 frame at 4 samples per pixel; argument = threads
//   BM_Frame720p          wall time of one 1280x720 frame at 16 samples per pixel, 2 bounces, all threads
//   BM_GeometryUpdate     per-frame scene update: new jelly vertices and normals (updateMesh: NaN check, copy,
//                         rtcUpdateGeometryBuffer, rtcCommitGeometry), the sphere moved, rtcCommitScene
// Run: build/bench/render_bench (or /tmp/build-render/render_bench); rates are in the counters column.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/global_control.h>

#include "render/camera.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "render/sampler.h"
#include "render/sampling.h"
#include "render/scene.h"
#include "sim/bodies/jelly.h"
#include "sim/surface.h"

namespace {

using namespace wobble::render;

struct BenchScene {
  Scene scene;
  ShapeId jelly = -1, ball = -1;
  TriangleMesh jelly_mesh;

  BenchScene() {
    wobble::JellyParams params;  // n = 10, size 4
    params.center = {0, 2.05, 0};
    params.rotation_axis = {0, 1, 0};
    params.rotation_deg = 30;
    const wobble::Body body = wobble::buildJelly("jelly", params);
    const wobble::SurfaceFrame frame = wobble::evaluateSurface(body.surface, body.x, 0);
    jelly_mesh.name = "jelly";
    jelly_mesh.positions = frame.positions;
    jelly_mesh.normals = frame.normals;
    jelly_mesh.uv = body.surface.uv;
    jelly_mesh.triangles = body.surface.triangles;

    const auto checker = std::make_shared<CheckerTexture>(Color(0.9f, 0.3f, 0.3f), Color(0.9f, 0.9f, 0.9f), 8);
    jelly = scene.addMesh(jelly_mesh, scene.addMaterial(Material::jelly("jelly", Color::Ones(), checker)));
    scene.addQuad("floor", Quad{{0, 0, 0}, {0, 1, 0}, 20, 4},
                  scene.addMaterial(Material::textured("wood", std::make_shared<WoodTexture>())));
    ball = scene.addSphere("ball", Sphere{{-4, 1.5f, -1}, 1.5f},
                           scene.addMaterial(Material::diffuse("red", Color(0.7f, 0.15f, 0.1f))));
    scene.lights.suns = {SunLight{}};
    scene.commit();
  }
};

BenchScene& benchScene() {
  static BenchScene s;
  return s;
}

CameraParams view(int width, int height) {
  CameraParams p;
  p.position = {3, 6, 14};
  p.look_at = {0, 2, 0};
  p.vfov_deg = 45;
  p.width = width;
  p.height = height;
  return p;
}

void BM_EmbreeIntersect1(benchmark::State& state) {
  const RTCScene rtc = benchScene().scene.embreeScene();
  const Camera camera(view(1280, 720));
  std::vector<RTCRayHit> rays;
  for (int y = 0; y < 720; y += 2)
    for (int x = 0; x < 1280; x += 2) {
      const Ray r = camera.ray(x + 0.5f, y + 0.5f);
      RTCRayHit rh{};
      rh.ray.org_x = r.origin.x(), rh.ray.org_y = r.origin.y(), rh.ray.org_z = r.origin.z();
      rh.ray.dir_x = r.direction.x(), rh.ray.dir_y = r.direction.y(), rh.ray.dir_z = r.direction.z();
      rh.ray.mask = 0xFFFFFFFFu;
      rays.push_back(rh);
    }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (RTCRayHit rh : rays) {
      rh.ray.tnear = 0;
      rh.ray.tfar = INFINITY;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtc, &context, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] =
      benchmark::Counter(double(rays.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EmbreeIntersect1)->Unit(benchmark::kMillisecond);

// The same camera rays as 4 x 4 pixel packets (rtcIntersect16): how much coherent primary rays gain from packets.
void BM_EmbreeIntersect16(benchmark::State& state) {
  const RTCScene rtc = benchScene().scene.embreeScene();
  const Camera camera(view(1280, 720));
  std::vector<RTCRayHit16> packets;
  for (int by = 0; by < 720; by += 8)
    for (int bx = 0; bx < 1280; bx += 8) {
      RTCRayHit16 p{};
      for (int k = 0; k < 16; ++k) {
        const Ray r = camera.ray(bx + 2 * (k % 4) + 0.5f, by + 2 * (k / 4) + 0.5f);  // every other pixel, as above
        p.ray.org_x[k] = r.origin.x(), p.ray.org_y[k] = r.origin.y(), p.ray.org_z[k] = r.origin.z();
        p.ray.dir_x[k] = r.direction.x(), p.ray.dir_y[k] = r.direction.y(), p.ray.dir_z[k] = r.direction.z();
        p.ray.mask[k] = 0xFFFFFFFFu;
      }
      packets.push_back(p);
    }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) int valid[16];
  std::fill(valid, valid + 16, -1);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (RTCRayHit16 p : packets) {
      for (int k = 0; k < 16; ++k) {
        p.ray.tnear[k] = 0;
        p.ray.tfar[k] = INFINITY;
        p.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, rtc, &context, &p);
      for (int k = 0; k < 16; ++k) hits += p.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] =
      benchmark::Counter(16.0 * double(packets.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EmbreeIntersect16)->Unit(benchmark::kMillisecond);

// Rays shaped like the renderer's: the camera rays of BM_RendererRays' frame (320 x 180, 4 jittered samples a pixel)
// and, from every hit, a shadow ray towards the sun and a cosine-distributed bounce, two bounces deep (what the path
// tracer traces, without its bounds shortcut), made once.
struct PathRays {
  std::vector<RTCRayHit> rays;  // camera rays and bounces, each path's in order
  std::vector<RTCRay> shadows;
};

const PathRays& pathRays() {
  static const PathRays made = [] {
    PathRays p;
    const RTCScene rtc = benchScene().scene.embreeScene();
    const Camera camera(view(320, 180));
    const Eigen::Vector3f sun = SunLight{}.direction.normalized();
    const auto toRay = [](const Ray& r) {
      RTCRay ray{};
      ray.org_x = r.origin.x(), ray.org_y = r.origin.y(), ray.org_z = r.origin.z();
      ray.dir_x = r.direction.x(), ray.dir_y = r.direction.y(), ray.dir_z = r.direction.z();
      ray.tfar = INFINITY;
      ray.mask = 0xFFFFFFFFu;
      return ray;
    };
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int y = 0; y < 180; ++y)
      for (int x = 0; x < 320; ++x) {
        const PixelSampler sampler(SamplerKind::Independent, std::uint64_t(y) * 320 + x, 0);
        for (std::uint32_t s = 0; s < 4; ++s) {
          const Eigen::Vector2f jitter = sampler.get2D(s, 0);
          Ray ray = camera.ray(float(x) + jitter.x(), float(y) + jitter.y());
          for (int bounce = 0; bounce <= 2; ++bounce) {
            RTCRayHit rh{};
            rh.ray = toRay(ray);
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            p.rays.push_back(rh);
            rtcIntersect1(rtc, &context, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
            Eigen::Vector3f n = Eigen::Vector3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
            if (n.dot(ray.direction) > 0) n = -n;
            const Eigen::Vector3f origin = offsetFromSurface(ray.at(rh.ray.tfar), n);
            if (sun.dot(n) > 0) p.shadows.push_back(toRay(Ray{origin, sun}));
            if (bounce == 2) break;
            const Eigen::Vector2f u = sampler.get2D(s, 2 + bounce);
            ray = Ray{origin, Frame(n).toWorld(sampleCosineHemisphere(u.x(), u.y())).normalized()};
          }
        }
      }
    return p;
  }();
  return made;
}

// Raw Embree on the renderer's kind of rays (pathRays), replayed: the loop only calls rtcIntersect1 and rtcOccluded1.
// Its rate is what a renderer of rtc*1 calls could reach on these rays with shading, sampling and hit records free:
// the ceiling BM_RendererRays is measured against.
void BM_EmbreePathRays(benchmark::State& state) {
  const RTCScene rtc = benchScene().scene.embreeScene();
  const PathRays& p = pathRays();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t hits = 0;
  for (auto _ : state) {
    for (RTCRayHit rh : p.rays) {
      rtcIntersect1(rtc, &context, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
    for (RTCRay ray : p.shadows) {
      rtcOccluded1(rtc, &context, &ray);
      hits += ray.tfar < 0;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] =
      benchmark::Counter(double(p.rays.size() + p.shadows.size()) * double(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["shadow_share"] = double(p.shadows.size()) / double(p.rays.size() + p.shadows.size());
}
BENCHMARK(BM_EmbreePathRays)->Unit(benchmark::kMillisecond);

// The intersection rays of pathRays alone (argument 0), and each made to wait for the one before (argument 1: its
// origin takes + 0 * the previous ray's hit distance, a data dependency the compiler keeps), as in a depth-first path
// tracer, where a bounce starts only once the hit before it is known. Equal rates say the processor gains nothing
// from overlapping independent rays, so a wavefront of scalar code would not either.
void BM_EmbreePathRaysChained(benchmark::State& state) {
  const RTCScene rtc = benchScene().scene.embreeScene();
  const PathRays& p = pathRays();
  const bool chained = state.range(0) != 0;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  std::size_t hits = 0;
  for (auto _ : state) {
    float previous = 0;  // the previous ray's hit distance (0 when it missed)
    for (RTCRayHit rh : p.rays) {
      if (chained) rh.ray.org_x += 0.0f * previous;
      rtcIntersect1(rtc, &context, &rh);
      const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      hits += hit;
      previous = hit ? rh.ray.tfar : 0.0f;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] =
      benchmark::Counter(double(p.rays.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_EmbreePathRaysChained)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_RendererRays(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, std::size_t(state.range(0)));
  const Camera camera(view(320, 180));
  RenderSettings settings;
  settings.samples_per_pixel = 4;
  std::uint64_t rays = 0, camera_rays = 0;
  for (auto _ : state) {
    RenderStats stats;
    benchmark::DoNotOptimize(render(benchScene().scene, camera, settings, &stats));
    rays += stats.rays;
    camera_rays += stats.camera_rays;
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
  state.counters["camera_rays_per_s"] = benchmark::Counter(double(camera_rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RendererRays)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Frame720p(benchmark::State& state) {
  const Camera camera(view(1280, 720));
  RenderSettings settings;
  settings.samples_per_pixel = 16;
  std::uint64_t rays = 0;
  for (auto _ : state) {
    RenderStats stats;
    benchmark::DoNotOptimize(render(benchScene().scene, camera, settings, &stats));
    rays += stats.rays;
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Frame720p)->Iterations(2)->Unit(benchmark::kSecond)->UseRealTime();

void BM_GeometryUpdate(benchmark::State& state) {
  BenchScene& s = benchScene();
  // A wobble: the jelly's vertices shifted by a smooth field, different each frame (prepared outside the loop).
  std::vector<std::vector<Eigen::Vector3f>> frames(8, s.jelly_mesh.positions);
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (auto& p : frames[f]) p += 0.05f * Eigen::Vector3f(std::sin(p.y() + f), 0, std::cos(p.x() + f));
  std::size_t frame = 0;
  for (auto _ : state) {
    s.scene.updateMesh(s.jelly, frames[frame % frames.size()], s.jelly_mesh.normals);
    s.scene.updateSphere(s.ball, Sphere{{-4, 1.5f + 0.01f * float(frame % 8), -1}, 1.5f});
    s.scene.commit();
    ++frame;
  }
  s.scene.updateMesh(s.jelly, s.jelly_mesh.positions, s.jelly_mesh.normals);  // leave the scene as it was
  s.scene.updateSphere(s.ball, Sphere{{-4, 1.5f, -1}, 1.5f});
  s.scene.commit();
  state.counters["frames_per_s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_GeometryUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
