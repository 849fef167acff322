// `wobble diff`: pairs of images or folders of them, idiff's numbers or FLIP, JUnit reports (see diff_command.h).
#include "app/commands/diff_command.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ostream>
#include <set>
#include <sstream>

#include "app/scene/input_error.h"
#include "image/png_io.h"
#include "io/atomic_file.h"
#include "io/text_table.h"

namespace fs = std::filesystem;

namespace wobble {

namespace {

using image::DiffCode;

std::string fixed(double v, int digits = 6) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

double flipStatistic(const image::FlipStats& s, const image::ImageF& map, const std::string& name) {
  if (name == "mean") return s.mean;
  if (name == "max") return s.max;
  return image::flipPercentile(map, std::stod(name.substr(1)));  // pNN, checked when parsed
}

// A heatmap into out/<name>.heatmap.png.
fs::path writeHeatmap(const fs::path& file, const image::ImageF& error) {
  fs::create_directories(file.parent_path());
  image::writePng(file, image::magmaHeatmap(error));
  return file;
}

struct Compared {
  DiffPair pair;
  image::ImageF error_map;  // per pixel, in [0, 1] (idiff metric: scaled by --scale)
};

Compared compareIdiff(const fs::path& a, const fs::path& b, const DiffCommandOptions& o, const fs::path& difference) {
  Compared c;
  const image::DiffResult r = image::diffFiles(a, b, o.idiff, difference, &c.error_map);
  for (float& e : c.error_map.pixels) e = std::min(1.0f, e * o.idiff.diff_scale);
  c.pair.code = r.code;
  c.pair.report = r.message;
  if (r.code == DiffCode::FileError) {
    c.pair.summary = r.message;
  } else {
    std::ostringstream s;
    s << "max " << io::formatNumber(r.max_error, 4) << ", " << r.fail_pixels << " of " << r.pixels << " pixels over "
      << io::formatNumber(o.idiff.fail, 4);
    if (o.idiff.perceptual) s << ", " << r.perceptual_failures << " failing the perceptual test";
    c.pair.summary = s.str();
  }
  return c;
}

Compared compareFlip(const fs::path& a, const fs::path& b, const DiffCommandOptions& o) {
  Compared c;
  image::ImageFile fa, fb;
  try {
    fa = image::readImageFile(a, o.idiff.channels);
    fb = image::readImageFile(b, o.idiff.channels);
  } catch (const std::exception& e) {
    c.pair.code = DiffCode::FileError;
    c.pair.summary = c.pair.report = e.what();
    return c;
  }
  if (fa.image.width != fb.image.width || fa.image.height != fb.image.height) {
    c.pair.code = DiffCode::Fail;
    c.pair.summary = "the images differ in size: " + std::to_string(fa.image.width) + " x " +
                     std::to_string(fa.image.height) + " against " + std::to_string(fb.image.width) + " x " +
                     std::to_string(fb.image.height) + " (FLIP compares images of one size)";
    c.pair.report = "  " + c.pair.summary + "\nFAILURE";
    return c;
  }
  const bool hdr = fa.linear || fb.linear;
  c.error_map = hdr ? image::hdrFlip(fa.image, fb.image, o.pixels_per_degree)
                    : image::ldrFlip(fa.image, fb.image, o.pixels_per_degree);
  const image::FlipStats s = image::flipStats(c.error_map);
  const auto exceeded = [&](const std::map<std::string, double>& limits, std::string& which) {
    for (const auto& [name, limit] : limits)
      if (const double v = flipStatistic(s, c.error_map, name); v > limit) {
        which = name + " " + fixed(v) + " > " + io::formatNumber(limit, 6);
        return true;
      }
    return false;
  };
  std::string why;
  c.pair.code = exceeded(o.flip_fail, why)   ? DiffCode::Fail
                : exceeded(o.flip_warn, why) ? DiffCode::Warning
                                             : DiffCode::Pass;
  std::ostringstream r;
  r << "  " << (hdr ? "HDR" : "LDR") << "-FLIP, " << io::formatNumber(o.pixels_per_degree, 4) << " pixels per degree";
  if (hdr) {
    const image::FlipExposures e = image::hdrFlipExposures(fa.image);
    r << ", exposures " << fixed(e.start, 4) << " to " << fixed(e.stop, 4) << " (" << e.count << ")";
  }
  r << "\n  Mean: " << fixed(s.mean) << "\n  Weighted median: " << fixed(s.weighted_median)
    << "\n  1st weighted quartile: " << fixed(s.weighted_q1) << "\n  3rd weighted quartile: " << fixed(s.weighted_q3)
    << "\n  Min: " << fixed(s.min) << "\n  Max: " << fixed(s.max) << "\n  p50: " << fixed(s.p50)
    << "\n  p95: " << fixed(s.p95) << "\n  p99: " << fixed(s.p99) << "\n";
  if (!why.empty()) r << "  " << why << "\n";
  r << image::verdict(c.pair.code);
  c.pair.report = r.str();
  c.pair.summary = "FLIP mean " + fixed(s.mean) + ", p95 " + fixed(s.p95) + ", max " + fixed(s.max) +
                   (why.empty() ? "" : " (" + why + ")");
  return c;
}

// Regular files under a folder, relative paths, sorted; names starting with '.' (and what is under them) skipped.
std::set<std::string> filesUnder(const fs::path& folder) {
  std::set<std::string> out;
  for (auto it = fs::recursive_directory_iterator(folder); it != fs::recursive_directory_iterator(); ++it) {
    if (it->path().filename().string().starts_with(".")) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) out.insert(fs::relative(it->path(), folder).generic_string());
  }
  return out;
}

std::string xmlEscaped(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += (u < 0x20 && ch != '\n' && ch != '\t') ? '?' : ch;  // no control characters in XML 1.0
    }
  }
  return out;
}

}  // namespace

std::map<std::string, double> parseFlipThresholds(const std::string& flag, const std::string& text) {
  std::map<std::string, double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto eq = item.find('=');
    const std::string name = eq == std::string::npos ? "mean" : item.substr(0, eq);
    const std::string value = eq == std::string::npos ? item : item.substr(eq + 1);
    bool ok = name == "mean" || name == "max";
    if (!ok && name.size() > 1 && name[0] == 'p') {
      try {
        std::size_t used = 0;
        const double q = std::stod(name.substr(1), &used);
        ok = used == name.size() - 1 && q >= 0 && q <= 100;
      } catch (const std::exception&) {
      }
    }
    double limit = 0;
    try {
      std::size_t used = 0;
      limit = std::stod(value, &used);
      ok = ok && used == value.size() && limit >= 0;
    } catch (const std::exception&) {
      ok = false;
    }
    if (!ok)
      throw InputError(flag + " '" + text + "': expected a FLIP limit such as 0.05 (the mean) or mean=0.05,p99=0.5 " +
                       "(statistics: mean, max, pNN for a percentile; limits >= 0)");
    out[name] = limit;
  }
  if (out.empty()) throw InputError(flag + " is empty: expected e.g. 0.05 or mean=0.05,p99=0.5");
  return out;
}

DiffReport runDiff(const DiffCommandOptions& o, std::ostream& log) {
  DiffReport report;
  std::error_code ec;
  report.folders = fs::is_directory(o.a, ec) && fs::is_directory(o.b, ec);
  // As idiff: an image and a folder compare the image with the folder's file of the same name.
  const fs::path single_b = !report.folders && fs::is_directory(o.b, ec) ? o.b / o.a.filename() : o.b;
  std::vector<std::pair<fs::path, image::ImageF>> heatmaps;  // written once all pairs are compared

  const auto compare = [&](const fs::path& a, const fs::path& b, const std::string& name, bool single) {
    const auto start = std::chrono::steady_clock::now();
    Compared c =
        o.metric == DiffMetric::Flip ? compareFlip(a, b, o) : compareIdiff(a, b, o, single ? o.out : fs::path());
    c.pair.name = name;
    c.pair.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool flagged = c.pair.code == DiffCode::Fail || c.pair.code == DiffCode::Warning;
    if (single && !o.heatmap.empty() && flagged && !c.error_map.pixels.empty()) {
      c.pair.heatmap = o.heatmap;
      heatmaps.emplace_back(o.heatmap, c.error_map);
    }
    if (!o.out.empty() && c.pair.code != DiffCode::FileError) {
      if (single) {  // the idiff metric's difference image is written by diffFiles
        const bool same =
            std::all_of(c.error_map.pixels.begin(), c.error_map.pixels.end(), [](float e) { return e == 0; });
        if (!(same && o.idiff.difference_only_if_different)) {  // -od: none for images that are the same
          if (o.metric == DiffMetric::Flip) heatmaps.emplace_back(o.out, std::move(c.error_map));
          c.pair.heatmap = o.out;
        }
      } else if (flagged && !c.error_map.pixels.empty()) {
        c.pair.heatmap = o.out / (name + ".heatmap.png");
        heatmaps.emplace_back(c.pair.heatmap, std::move(c.error_map));
      }
    }
    report.pairs.push_back(std::move(c.pair));
  };

  if (report.folders) {
    const std::set<std::string> golden = filesUnder(o.a), fresh = filesUnder(o.b);
    std::set<std::string> all = golden;
    all.insert(fresh.begin(), fresh.end());
    const bool common = std::any_of(golden.begin(), golden.end(), [&](const auto& n) { return fresh.count(n) > 0; });
    if (!common) {
      DiffPair p;
      p.name = o.a.string() + " vs " + o.b.string();
      p.code = DiffCode::FileError;
      p.summary = p.report = o.a.string() + " and " + o.b.string() + ": the folders have no file in common (" +
                             std::to_string(golden.size()) + " and " + std::to_string(fresh.size()) +
                             " files): nothing to compare";
      report.pairs.push_back(p);
    }
    for (const std::string& name : common ? all : std::set<std::string>{}) {
      if (!fresh.count(name) || !golden.count(name)) {
        DiffPair p;
        p.name = name;
        p.code = DiffCode::Fail;
        p.summary = !fresh.count(name) ? "missing: in " + o.a.string() + " but not in " + o.b.string()
                                       : "extra: in " + o.b.string() + " but not in " + o.a.string();
        p.report = p.summary + "\nFAILURE";
        report.pairs.push_back(p);
      } else {
        compare(o.a / name, o.b / name, name, false);
      }
    }
  } else {
    compare(o.a, single_b, o.a.string() + " vs " + single_b.string(), true);
  }
  for (const DiffPair& p : report.pairs) report.worst = std::max(report.worst, p.code);

  // Outputs: heatmaps, then the report.
  for (const auto& [file, error] : heatmaps) writeHeatmap(file, error);
  if (!o.junit.empty())
    io::writeFileAtomically(o.junit,
                            junitXml(report, report.folders ? o.a.string() + " vs " + o.b.string() : "wobble diff"));

  if (o.quiet) return report;
  if (!report.folders) {
    const DiffPair& p = report.pairs.front();
    if (p.code == DiffCode::FileError) {
      log << p.report << "\n";
    } else {
      log << "Comparing \"" << o.a.string() << "\" and \"" << single_b.string() << "\"\n";
      if (o.verbose && o.all_subimages) {  // idiff -a -v: each subimage's size, of the first image
        const image::ImageF a = image::readImageFile(o.a, o.idiff.channels).image;
        log << a.width << " x " << a.height << ", " << a.channels << " channels\n";
      }
      // idiff prints the numbers only when the images are not the same (or with -v); FLIP's always.
      const bool numbers = o.verbose || p.code != DiffCode::Pass || o.metric == DiffMetric::Flip;
      const std::string& r = p.report;
      const auto last = r.rfind('\n');
      log << (numbers ? r : (last == std::string::npos ? r : r.substr(last + 1))) << "\n";
    }
    return report;
  }
  for (const DiffPair& p : report.pairs) {
    log << image::verdict(p.code) << "  " << p.name << ": " << p.summary << "\n";
    if (o.verbose) log << p.report << "\n";
  }
  log << "\n" << diffTable(report) << image::verdict(report.worst) << "\n";
  return report;
}

std::string diffTable(const DiffReport& report) {
  io::TextTable table;
  table.header = {"image", "result", "details"};
  int counts[5] = {};
  for (const DiffPair& p : report.pairs) {
    ++counts[static_cast<int>(p.code)];
    table.add(
        {p.name, image::verdict(p.code), p.summary + (p.heatmap.empty() ? "" : "; heatmap " + p.heatmap.string())});
  }
  return table.markdown() + "\n" + std::to_string(report.pairs.size()) + " pairs: " + std::to_string(counts[0]) +
         " pass, " + std::to_string(counts[1]) + " warning, " + std::to_string(counts[2]) + " failure, " +
         std::to_string(counts[4]) + " file error\n";
}

std::string junitXml(const DiffReport& report, const std::string& suite) {
  int failures = 0, errors = 0;
  double seconds = 0;
  for (const DiffPair& p : report.pairs) {
    failures += p.code == DiffCode::Fail;
    errors += p.code == DiffCode::FileError;
    seconds += p.seconds;
  }
  std::ostringstream x;
  const auto attrs = [&] {
    return "tests=\"" + std::to_string(report.pairs.size()) + "\" failures=\"" + std::to_string(failures) +
           "\" errors=\"" + std::to_string(errors) + "\" time=\"" + fixed(seconds, 3) + "\"";
  };
  x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"wobble diff\" " << attrs() << ">\n"
    << "  <testsuite name=\"" << xmlEscaped(suite) << "\" " << attrs() << " skipped=\"0\">\n";
  for (const DiffPair& p : report.pairs) {
    x << "    <testcase classname=\"wobble.diff\" name=\"" << xmlEscaped(p.name) << "\" time=\"" << fixed(p.seconds, 3)
      << "\"";
    const std::string details = p.report + (p.heatmap.empty() ? "" : "\nheatmap: " + p.heatmap.string());
    if (p.code == DiffCode::Fail)
      x << ">\n      <failure type=\"FAILURE\" message=\"" << xmlEscaped(p.summary) << "\">" << xmlEscaped(details)
        << "</failure>\n    </testcase>\n";
    else if (p.code == DiffCode::FileError)
      x << ">\n      <error type=\"FILE ERROR\" message=\"" << xmlEscaped(p.summary) << "\">" << xmlEscaped(details)
        << "</error>\n    </testcase>\n";
    else
      x << ">\n      <system-out>" << xmlEscaped(std::string(image::verdict(p.code)) + ": " + p.summary)
        << "</system-out>\n    </testcase>\n";
  }
  x << "  </testsuite>\n</testsuites>\n";
  return x.str();
}

}  // namespace wobble
