#include "app/compare/compare_report.h"

#include <algorithm>
#include <sstream>

#include "app/compare/tile_label.h"
#include "app/study/study_stability.h"
#include "io/text_table.h"

namespace wobble {
namespace {

Outcome outcomeOf(const CompareRow& r) {
  if (r.blow_up_time) return Outcome::BlewUp;
  return r.lost_shape_time ? Outcome::LostShape : Outcome::Stable;
}

std::string when(const CompareRow& r) {
  if (r.blow_up_time) return "t = " + labelSeconds(*r.blow_up_time) + " s, step " + std::to_string(r.blow_up_step);
  if (r.lost_shape_time) return "from t = " + labelSeconds(*r.lost_shape_time) + " s";
  return "";
}

}  // namespace

std::string compareMarkdown(const CompareSummary& s) {
  std::ostringstream md;
  md << "# wobble compare: " << s.scene << "\n\n";
  md << "Varied:";
  for (const std::string& v : s.vary) md << " `" << v << "`";
  md << "; every variant: " << (s.common.empty() ? "the scene as it is" : "`" + s.common + "`") << ".\n\n";
  if (!s.video.empty()) md << "Video: " << s.video << (s.layout.empty() ? "" : ", " + s.layout) << ".\n\n";

  const auto perStep = [](const CompareRow& r) { return r.steps > 0 ? r.simulate_seconds / double(r.steps) : 0.0; };
  double cheapest = 0;
  for (const CompareRow& r : s.rows)
    if (perStep(r) > 0 && (cheapest == 0 || perStep(r) < cheapest)) cheapest = perStep(r);
  std::vector<std::string> header = {"variant",       "integrator", "dt (s)", "steps",
                                     "simulated (s)", "outcome",    "when",   "max strain"};
  if (s.estimate_error) header.push_back("estimated error, max (m)");
  for (const char* h : {"simulate (s)", "per step (us)", "per step vs cheapest", "wall (s)", "folder"})
    header.push_back(h);
  io::TextTable t{header, {}};
  for (const CompareRow& r : s.rows) {
    std::vector<std::string> row = {r.label,
                                    r.integrator,
                                    io::formatNumber(r.dt),
                                    std::to_string(r.steps),
                                    io::formatNumber(r.simulated_time, 4),
                                    toString(outcomeOf(r)),
                                    when(r),
                                    io::formatNumber(r.max_strain, 3)};
    if (s.estimate_error)
      row.push_back(r.estimated_error
                        ? io::formatNumber(*r.estimated_error, 3) + (r.estimate_note.empty() ? "" : " (partial)")
                        : "");
    row.push_back(io::formatNumber(r.simulate_seconds, 3));
    row.push_back(io::formatNumber(1e6 * perStep(r), 3));
    row.push_back(cheapest > 0 ? "x " + io::formatNumber(perStep(r) / cheapest, 3) : "");
    row.push_back(io::formatNumber(r.wall_seconds, 3));
    row.push_back("`" + r.folder + "/`");
    t.add(row);
  }
  md << t.markdown() << "\n";
  md << "Outcomes as in `wobble study stability`: **blew-up** is the blow-up rule (a NaN or a particle with "
        "|v|^2 > 1e6; the run stops there), **lost-shape** a largest spring strain |l - rest| / rest over "
     << io::formatNumber(s.strain_bound)
     << " at a frame, **stable** neither; max strain is over the frames reached.\n\n";
  md << "Times: *simulate* is each run's simulation time (its run.json), *wall* from its start to its run.json "
        "(meshes and point cache written); ";
  if (s.pieces > 0)
    md << "gathered from " << s.pieces << " pieces run apart (`--piece I/" << s.pieces
       << "`, then `--gather`): each variant's times are those it took in its piece, up to ";
  md << s.jobs << " run(s) at a time on " << (s.pieces > 0 ? "up to " : "") << s.threads
     << " hardware thread(s), so runs that shared a machine are slower than alone (`--jobs 1` for timings).\n\n";
  md << "Each variant is the plain run:\n\n```sh\n";
  for (const CompareRow& r : s.rows) md << r.command << "\n";
  md << "```\n";
  return md.str();
}

}  // namespace wobble
