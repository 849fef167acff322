// `wobble diff A B`: two images, or two folders of them (a suite of goldens against new renders), compared with
// idiff 2.4's numbers and exit codes (image/image_diff.h, -p: image/yee.h) or with FLIP
// (image/flip.h: LDR-FLIP for display images, HDR-FLIP when either file holds linear values: EXR, HDR, PFM).
//
// An image and a folder: the image against the folder's file of the same name (as idiff).
// Folders: the files of the same relative path in both (sub-folders included, names starting with '.' skipped) are
// compared pair by pair; a file in only one folder is a failing pair ("missing" or "extra"); folders with no file in
// common are a file error (4) naming both. One line per pair, then a table of all pairs and the counts.
// Exit status: the worst pair's (0 pass, 1 warning, 2 failure, 4 file error).
// Outputs (written atomically, and only once every pair is compared, so an error leaves none half-written):
//   out    one pair: the difference image |A - B| * scale (idiff metric, as idiff -o) or the FLIP heatmap (magma);
//          folders: a folder receiving <name>.heatmap.png for each pair that warns or fails (the per-pixel error,
//          idiff metric: max over channels * scale, clamped to 1; FLIP: its error), through the magma colour map
//   heatmap  one pair: that heatmap, written when the pair warns or fails (with either metric)
//   junit  a JUnit XML report, one test case per image pair (<failure> for failing and missing pairs, <error> for
//          file errors), which CI systems (GitLab, Jenkins, GitHub actions) read
// FLIP thresholds (fail, warn): "mean=0.05,p99=0.5" or a bare number (the mean); statistics: mean, max, pNN (the
// NN-th percentile of the pixels' errors, e.g. p95). A pair fails when any fail threshold is exceeded, else warns when
// any warn threshold is. Default: fail when the mean exceeds 0 (any difference), as idiff's default.
#pragma once
#include <filesystem>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "image/flip.h"
#include "image/image_diff.h"

namespace wobble {

enum class DiffMetric { Idiff, Flip };

struct DiffCommandOptions {
  std::filesystem::path a, b;  // two files, or two folders (golden, new)
  std::filesystem::path out, junit, heatmap;
  DiffMetric metric = DiffMetric::Idiff;
  image::DiffOptions idiff;  // thresholds and channels (the channel choice applies to FLIP too)
  std::map<std::string, double> flip_fail = {{"mean", 0.0}}, flip_warn;  // statistic -> limit
  double pixels_per_degree = image::kFlipDefaultPixelsPerDegree;
  bool verbose = false;        // idiff's report for passing pairs too
  bool quiet = false;          // print nothing (idiff -q)
  bool all_subimages = false;  // idiff -a: with verbose, the image's size and channels (its one subimage) too
};

// "mean=0.05,p99=0.5" or "0.05" -> statistic -> limit. Throws InputError naming the flag for anything else.
std::map<std::string, double> parseFlipThresholds(const std::string& flag, const std::string& text);

struct DiffPair {
  std::string name;  // the relative path (folders) or "A vs B"
  image::DiffCode code = image::DiffCode::Pass;
  std::string summary;  // one line: the key numbers or why it failed
  std::string report;   // the full report (idiff's, or FLIP's pooled values), ending in the verdict
  double seconds = 0;
  std::filesystem::path heatmap;  // written for this pair, if any
};

struct DiffReport {
  std::vector<DiffPair> pairs;
  image::DiffCode worst = image::DiffCode::Pass;
  bool folders = false;
  int exitCode() const { return static_cast<int>(worst); }
};

// Compares, prints to `log` (the per-pair lines and, for folders, the table), writes the outputs. Never throws for
// unreadable images (they are file errors, 4); throws only when an output cannot be written.
DiffReport runDiff(const DiffCommandOptions& options, std::ostream& log);

// The table of a report's pairs (Markdown: image, result, details) and the line of counts.
std::string diffTable(const DiffReport& report);

// The JUnit XML text of a report (suite name given).
std::string junitXml(const DiffReport& report, const std::string& suite);

}  // namespace wobble
