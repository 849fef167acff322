// A jelly among other bodies collides with itself by default (docs/body-contact.md, "Self-contact"). Oracle: the
// independent triangle-triangle test of tests/sim/triangle_intersection.h (Moller 1997). Two soft jellies in a well
// barely wider than they are (bench/scenes/jelly_well.toml), the upper twenty times heavier: it lands on the lower one
// and presses it into the well, whose surface folds. With the shipped defaults (no self_contact key) no two of the
// lower jelly's triangles intersect at any frame; with self_contact = false (the control, so that the test can fail)
// they do.
#include <gtest/gtest.h>

#include <algorithm>

#include "app/commands/run_command.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"
#include "tests/sim/triangle_intersection.h"

namespace wobble {
namespace {

class SelfContactDefault : public testing::ScratchDir {
 protected:
  // The lower jelly's most intersecting pairs of its own triangles at any frame.
  int worstFold(const std::vector<std::string>& sets) {
    RunOptions o;
    o.scene = testing::sourceDir() / "bench/scenes/jelly_well.toml";
    o.out = dir() / "out";
    o.render.render = "none";
    o.progress = false;
    o.sets = sets;
    const SceneFile scene = loadRunScene(o);
    const auto& bodies = scene.system->bodies();
    const BodySlot& low =
        *std::find_if(bodies.begin(), bodies.end(), [](const BodySlot& b) { return b.body.name == "low"; });
    testing::ParticleTriangles tris;
    testing::addSurface(tris, low.body.surface, low.first, 0);
    int worst = 0, frames = 0;
    o.on_frame = [&](int, const VecX& x) {
      ++frames;
      worst = std::max(worst, testing::intersectingPairs(tris, x));
    };
    const RunReport r = runScene(o);
    EXPECT_FALSE(r.blow_up) << r.blow_up_message;
    EXPECT_EQ(frames, scene.frameCount());
    return worst;
  }
};

TEST_F(SelfContactDefault, SqueezedJellyInAWellDoesNotFoldThroughItself) {
  EXPECT_EQ(worstFold({}), 0);
  EXPECT_GT(worstFold({"bodies.low.self_contact=false", "bodies.high.self_contact=false"}), 0);
}

}  // namespace
}  // namespace wobble
