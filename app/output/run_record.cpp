#include "app/output/run_record.h"

#include <fstream>

#include <nlohmann/json.hpp>

#include "app/scene/input_error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace wobble {

std::string RunRecord::framesText() const {
  return "the run wrote frames " + std::to_string(first_frame) + ":" + std::to_string(last_frame);
}

RunRecord readRunRecord(const fs::path& out, const std::string& missing) {
  const fs::path file = out / "run.json";
  if (!fs::is_regular_file(file))
    throw InputError(out.string() + ": no run.json: not the folder of a wobble run" + missing);
  RunRecord run;
  try {
    const json j = json::parse(std::ifstream(file));
    run.scene = j.at("scene").get<std::string>();
    if (j.contains("carried")) {
      for (const json& c : j.at("carried"))
        run.carried.push_back(
            {c.at("path").get<std::string>(), c.at("hash").get<std::string>(), c.at("source").get<std::string>()});
      run.scene = out / run.scene;  // relative to the folder, wherever it is now
    }
    if (j.contains("overrides")) run.overrides = j.at("overrides").get<std::vector<std::string>>();
    run.first_frame = j.at("frames").at("first").get<int>();
    run.last_frame = run.first_frame + j.at("frames").at("written").get<int>() - 1;
    run.fps = j.at("fps").get<double>();
  } catch (const json::exception& e) {
    throw InputError(file.string() + ": not a wobble run.json (" + e.what() + ")");
  }
  if (run.last_frame < run.first_frame) throw InputError(file.string() + ": the run wrote no frame");
  return run;
}

SceneFile loadRecordedScene(const fs::path& out, const RunRecord& run, const std::vector<std::string>& sets,
                            const SceneFlags& flags) {
  checkCarriedFiles(out, run.carried);
  // The carried scene has the run's overrides in it (and its file keys point at the copies): only an older folder's
  // scene file needs them laid over it again.
  std::vector<std::string> overrides = run.carried.empty() ? run.overrides : std::vector<std::string>{};
  overrides.insert(overrides.end(), sets.begin(), sets.end());
  if (!fs::is_regular_file(run.scene))
    throw InputError(run.scene.string() + ": scene file not found (" + (out / "run.json").string() +
                     " names it; a folder of a wobble run from before run folders carried their scene needs the "
                     "project it was made from, run from the folder the run started in)");
  return loadScene(run.scene, overrides, flags);
}

}  // namespace wobble
