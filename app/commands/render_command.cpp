#include "app/commands/render_command.h"

#include <algorithm>

#include "app/commands/frame_range.h"
#include "app/commands/wall_clock.h"
#include "app/output/disk_budget.h"
#include "app/output/frame_name.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence.h"
#include "app/output/obj_sequence_reader.h"
#include "app/output/output_folder.h"
#include "app/output/progress.h"
#include "app/output/run_record.h"
#include "app/pictures/frame_output.h"
#include "app/run/sequence_poser.h"
#include "app/scene/input_error.h"
#include "app/scene/scene_file.h"
#include "io/writable_place.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

fs::path objPath(const fs::path& dir, const Body& body, int frame) { return objFramePath(dir, body.name, frame); }

}  // namespace

RenderCommandReport renderSequence(const RenderCommandOptions& given) {
  RenderCommandOptions options = given;
  SceneFile scene = [&] {
    if (options.scene) return loadScene(*options.scene, options.sets, renderFlagSettings(options.render));
    // The run's own scene: MESH_DIR is OUT (holding run.json) or OUT/mesh.
    fs::path out = options.mesh_dir.lexically_normal();
    if (out.filename().empty()) out = out.parent_path();  // "out/x/mesh/" -> "out/x/mesh"
    if (!fs::is_regular_file(out / "run.json") && fs::is_regular_file(out.parent_path() / "run.json"))
      out = out.parent_path();
    else options.mesh_dir = out / "mesh";
    const RunRecord run = readRunRecord(out, "; name the scene the sequence was made from with --scene FILE");
    SceneFile recorded = loadRecordedScene(out, run, options.sets, renderFlagSettings(options.render));
    if (!options.render.render && !FrameOutput::wanted(recorded)) {  // a run that only simulated (--render none)
      options.render.render = "png";                                 // is rendered to its PNGs unless --render says
      recorded = loadRecordedScene(out, run, options.sets, renderFlagSettings(options.render));
    }
    return recorded;
  }();
  RenderCommandReport report;
  // A piece (--frames) makes no video of its own unless --video asks: the pieces of a split render would each write
  // OUT/<scene>.mp4 of their frames; `wobble video OUT` joins them all at the end.
  report.piece_without_video = options.frames && scene.render.options.video && !options.render.video;
  if (report.piece_without_video) scene.render.options.video = false;
  if (!FrameOutput::wanted(scene))
    throw InputError("nothing to render: render.png and render.exr are both false (--render png, exr or png,exr)");
  if (!fs::is_directory(options.mesh_dir))
    throw InputError(options.mesh_dir.string() + ": no such folder (MESH_DIR is a run's OUT/mesh)");

  const auto& bodies = scene.system->bodies();
  const Body& lead = bodies.front().body;
  if (options.frames) {
    std::tie(report.first_frame, report.last_frame) = parseFrameRange(*options.frames, scene.frameCount());
  } else {  // every frame the folder holds: the first one there up to the last of an unbroken run
    int k = 1;
    while (k <= scene.frameCount() && !fs::exists(objPath(options.mesh_dir, lead, k))) ++k;
    if (k > scene.frameCount())
      throw InputError(options.mesh_dir.string() + ": no " + frameFileName(lead.name, 1, "obj") + " ... for scene " +
                       scene.name + "'s body '" + lead.name + "'");
    report.first_frame = k;
    while (k + 1 <= scene.frameCount() && fs::exists(objPath(options.mesh_dir, lead, k + 1))) ++k;
    report.last_frame = k;
  }
  // Check the inputs before writing anything: every file of the range, and the first frame's topology.
  for (int k = report.first_frame; k <= report.last_frame; ++k)
    for (const BodySlot& slot : bodies)
      if (!fs::is_regular_file(objPath(options.mesh_dir, slot.body, k)))
        throw InputError(objPath(options.mesh_dir, slot.body, k).string() + ": file not found");
  std::vector<SurfaceFrame> first;
  try {
    first = readObjFrame(options.mesh_dir, scene, report.first_frame);
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }

  fs::path mesh_dir = options.mesh_dir.lexically_normal();
  if (mesh_dir.filename().empty()) mesh_dir = mesh_dir.parent_path();  // "out/x/mesh/" -> "out/x/mesh"
  report.out = options.out.value_or(mesh_dir.has_parent_path() ? mesh_dir.parent_path() : fs::path("."));
  io::checkWritable(report.out);  // the OS's reason first: the budget speaks only for a writable place
  checkDiskBudget(estimateRenderOutput(scene, report.first_frame, report.last_frame), report.out);
  // Only the frames of the range are written: pieces of a split render share the folder.
  const OutputFolder folder(report.out, OutputFolder::Access::shared);
  const auto start = Clock::now();
  FrameOutput pictures(scene, report.out, options.skip_existing);
  SequencePoser poser(scene);

  // The follow camera's smoothing runs over the frames before the range too, as in the run (camera_rig.h). Motion
  // blur blends the first frame's poses from the one before it, when the sequence has it (shutter.h).
  const int before = report.first_frame - 1;
  const bool blur_from_before = scene.render.camera.shutter > 0 && before >= 1 &&
                                std::all_of(bodies.begin(), bodies.end(), [&](const BodySlot& slot) {
                                  return fs::exists(objPath(options.mesh_dir, slot.body, before));
                                });
  const auto previous = [&](int k, int only) {
    try {
      return readObjFrame(options.mesh_dir, scene, k, k == before && blur_from_before ? -1 : only);
    } catch (const std::runtime_error& e) {
      throw InputError(e.what());
    }
  };
  int history = report.first_frame;
  if (const int followed = poser.followedBody(); followed >= 0) {
    while (history > 1 && fs::exists(objPath(options.mesh_dir, bodies[followed].body, history - 1))) --history;
    for (int k = history; k < report.first_frame; ++k) poser.observe(k, previous(k, followed));
  } else if (blur_from_before) {
    poser.observe(before, previous(before, -1));
  }

  Progress progress(scene.name + " (render)", report.last_frame - report.first_frame + 1);
  for (int k = report.first_frame; k <= report.last_frame && !interrupted(); ++k) {
    poser.observe(k, k == report.first_frame ? first : readObjFrame(options.mesh_dir, scene, k));
    pictures.frame(poser.posed());
    progress.update(k - report.first_frame + 1);
  }
  progress.finish();
  report.frames_rendered = pictures.framesRendered();
  report.frames_skipped = pictures.framesSkipped();
  report.video = pictures.finish();
  report.seconds = secondsSince(start);
  return report;
}

}  // namespace wobble
