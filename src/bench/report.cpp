// The benchmark's outputs: a markdown table, JSON, an HTML page of SVG bar
// charts and one SVG chart of every structure's rays/s relative to Embree.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "mbrt/bench.h"

namespace mbrt::bench {
namespace {

std::string fmt(double v, int digits = 3) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}
template <class T>
std::string opt(const std::optional<T>& v, int digits = 3) {
  return v ? fmt(double(*v), digits) : "n/a";
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (uint8_t(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}
std::string jsonNum(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
template <class T>
std::string jsonOpt(const std::optional<T>& v) {
  return v ? jsonNum(double(*v)) : "null";
}

const Result* find(const Report& r, const std::string& scene, const std::string& accel) {
  for (const Result& x : r.results)
    if (x.scene == scene && x.accel == accel) return &x;
  return nullptr;
}

std::vector<std::string> sceneOrder(const Report& r) {
  std::vector<std::string> s;
  for (const Result& x : r.results)
    if (s.empty() || s.back() != x.scene) s.push_back(x.scene);
  return s;
}

std::string ratio(double a, const Result* base, double Result::*field) {
  if (!base || !(base->*field > 0)) return "–";
  return fmt(a / (base->*field), 3);
}

}  // namespace

std::string toMarkdown(const Report& report) {
  std::ostringstream out;
  out << "mbrt bench — " << report.cpu << ", " << report.threads << " threads, commit " << report.commit << "\n";
  for (const std::string& scene : sceneOrder(report)) {
    const Result* interp = find(report, scene, "bvh-interp");
    const Result* embree = find(report, scene, "embree");
    const Result* frozen = find(report, scene, "frozen");
    size_t prims = 0, rays = 0;
    for (const Result& r : report.results)
      if (r.scene == scene) {
        prims = std::max(prims, r.primitives);
        if (r.accel != "frozen") rays = r.rays;
      }
    out << "\n### " << scene << " (" << prims << " primitives, " << rays << " rays)\n\n";
    out << "| accel | build s | Mprims/s | MB | peak MB | SAH | steps | box tests | isects | Mrays/s 1t | Mrays/s mt"
           " | mt ÷ bvh-interp | mt ÷ embree | mem ÷ embree | build ÷ embree | frozen set Mrays/s | ÷ frozen | mismatches |\n";
    out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const Result& r : report.results) {
      if (r.scene != scene) continue;
      std::string mism = std::to_string(r.mismatchesBrute) + "/" + std::to_string(r.bruteChecked) + " brute";
      if (r.mismatchesEmbree) mism += ", " + std::to_string(*r.mismatchesEmbree) + " embree";
      out << "| " << r.accel << " | " << fmt(r.buildS) << " | " << fmt(r.buildMprims) << " | "
          << fmt(double(r.bytes) / 1e6) << " | " << fmt(double(r.peakBuildBytes) / 1e6) << " | " << opt(r.sah)
          << " | " << opt(r.stepsMean) << " | " << opt(r.boxTestsMean) << " | " << opt(r.isectsMean) << " | "
          << fmt(r.mraysSt) << " | " << fmt(r.mraysMt) << " | " << ratio(r.mraysMt, interp, &Result::mraysMt)
          << " | " << ratio(r.mraysMt, embree, &Result::mraysMt) << " | "
          << (embree && embree->bytes ? fmt(double(r.bytes) / double(embree->bytes)) : "–") << " | "
          << ratio(r.buildS, embree, &Result::buildS) << " | " << fmt(r.frozenSet.mraysMt) << " | "
          << (frozen && frozen->frozenSet.mraysMt > 0 ? fmt(r.frozenSet.mraysMt / frozen->frozenSet.mraysMt) : "–")
          << " | " << mism << " |\n";
    }
    for (const Result& r : report.results)
      if (r.scene == scene && r.timedRays < r.rays)
        out << "\n`" << r.accel << "` was timed on " << r.timedRays << " of the " << r.rays
            << " rays, evenly spread over the set (its full passes would exceed the time budget); mismatches are over those.\n";
    for (const Result& r : report.results) {
      const size_t full = std::min(report.options.countSample, r.rays);
      if (r.scene == scene && r.countedRays > 0 && r.countedRays < full)
        out << "\n`" << r.accel << "`'s counters are over " << r.countedRays << " of the " << full
            << " sampled rays (counting them all would exceed its time budget).\n";
    }
  }
  if (!report.notes.empty()) {
    out << "\nNotes:\n";
    for (const std::string& n : report.notes) out << "- " << n << "\n";
  }
  out << "\n`frozen`: build and memory per tree (" << report.options.frozenTimes
      << " trees); its row traces the frozen set. Embree exposes no tree: SAH and counters n/a.\n";
  return out.str();
}

std::string toJson(const Report& report) {
  std::ostringstream o;
  o << "{\n  \"machine\": {\"cpu\": " << jsonString(report.cpu) << ", \"threads\": " << report.threads
    << ", \"commit\": " << jsonString(report.commit) << "},\n";
  o << "  \"options\": {\"size\": " << jsonNum(report.options.size) << ", \"width\": " << report.options.width
    << ", \"height\": " << report.options.height << ", \"frozen_times\": " << report.options.frozenTimes
    << ", \"repeats\": " << report.options.repeats << ", \"seed\": " << report.options.seed << "},\n";
  o << "  \"results\": [";
  for (size_t i = 0; i < report.results.size(); ++i) {
    const Result& r = report.results[i];
    o << (i ? ",\n" : "\n") << "    {\"scene\": " << jsonString(r.scene) << ", \"accel\": " << jsonString(r.accel)
      << ", \"primitives\": " << r.primitives << ", \"build_s\": " << jsonNum(r.buildS)
      << ", \"build_mprims\": " << jsonNum(r.buildMprims) << ", \"builds\": " << r.builds
      << ", \"bytes\": " << r.bytes << ", \"peak_build_bytes\": " << r.peakBuildBytes
      << ", \"sah\": " << jsonOpt(r.sah) << ", \"steps_mean\": " << jsonOpt(r.stepsMean)
      << ", \"steps_max\": " << jsonOpt(r.stepsMax) << ", \"box_tests_mean\": " << jsonOpt(r.boxTestsMean)
      << ", \"isects_mean\": " << jsonOpt(r.isectsMean) << ", \"isects_max\": " << jsonOpt(r.isectsMax)
      << ", \"rays\": " << r.rays << ", \"timed_rays\": " << r.timedRays << ", \"counted_rays\": " << r.countedRays << ", \"mrays_st\": " << jsonNum(r.mraysSt)
      << ", \"mrays_mt\": " << jsonNum(r.mraysMt) << ", \"mismatches\": " << r.mismatches
      << ", \"mismatches_brute\": " << r.mismatchesBrute << ", \"brute_checked\": " << r.bruteChecked
      << ", \"mismatches_embree\": " << jsonOpt(r.mismatchesEmbree) << ", \"frozen_set\": {\"rays\": "
      << r.frozenSet.rays << ", \"timed_rays\": " << r.frozenSet.timedRays
      << ", \"mrays_mt\": " << jsonNum(r.frozenSet.mraysMt)
      << ", \"steps_mean\": " << jsonOpt(r.frozenSet.stepsMean)
      << ", \"isects_mean\": " << jsonOpt(r.frozenSet.isectsMean)
      << ", \"mismatches\": " << r.frozenSet.mismatches << "}}";
  }
  o << "\n  ],\n  \"notes\": [";
  for (size_t i = 0; i < report.notes.size(); ++i) o << (i ? ", " : "") << jsonString(report.notes[i]);
  o << "]\n}\n";
  return o.str();
}

namespace {

std::string escapeXml(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

// A horizontal bar chart as inline SVG.
std::string barChart(const std::string& title, const std::vector<std::pair<std::string, double>>& bars,
                     const std::string& unit) {
  const int rowH = 22, labelW = 110, chartW = 320, top = 24;
  double maxV = 0;
  for (const auto& b : bars) maxV = std::max(maxV, b.second);
  std::ostringstream s;
  const int h = top + rowH * int(bars.size()) + 6;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << labelW + chartW + 90 << "' height='" << h << "'>";
  s << "<text x='4' y='16' font-size='13' font-weight='bold'>" << escapeXml(title) << "</text>";
  for (size_t i = 0; i < bars.size(); ++i) {
    const int y = top + rowH * int(i);
    const double w = maxV > 0 ? bars[i].second / maxV * chartW : 0;
    const char* color = bars[i].first == "embree" ? "#d08030" : (bars[i].first == "frozen" ? "#888" : "#3a78b8");
    s << "<text x='" << labelW - 6 << "' y='" << y + 15 << "' font-size='12' text-anchor='end'>"
      << escapeXml(bars[i].first) << "</text>";
    s << "<rect x='" << labelW << "' y='" << y + 3 << "' width='" << w << "' height='" << rowH - 6 << "' fill='"
      << color << "'/>";
    s << "<text x='" << labelW + w + 4 << "' y='" << y + 15 << "' font-size='11'>" << fmt(bars[i].second) << " "
      << unit << "</text>";
  }
  s << "</svg>";
  return s.str();
}

}  // namespace

std::string toHtml(const Report& report) {
  std::ostringstream o;
  o << "<!DOCTYPE html><html><head><meta charset='utf-8'><title>mbrt bench</title>"
       "<style>body{font-family:sans-serif;margin:20px} .row{display:flex;flex-wrap:wrap;gap:16px}</style>"
       "</head><body><h1>mbrt bench</h1><p>"
    << escapeXml(report.cpu) << ", " << report.threads << " threads, commit " << escapeXml(report.commit)
    << "</p>";
  for (const std::string& scene : sceneOrder(report)) {
    std::vector<std::pair<std::string, double>> mem, speed, build;
    for (const Result& r : report.results) {
      if (r.scene != scene) continue;
      mem.push_back({r.accel, double(r.bytes) / 1e6});
      speed.push_back({r.accel, r.mraysMt});
      build.push_back({r.accel, r.buildS});
    }
    o << "<h2>" << escapeXml(scene) << "</h2><div class='row'>" << barChart("memory", mem, "MB")
      << barChart("rays/s, all threads", speed, "Mrays/s") << barChart("build time", build, "s") << "</div>";
  }
  o << "<pre>" << escapeXml(toMarkdown(report)) << "</pre></body></html>\n";
  return o.str();
}

}  // namespace mbrt::bench

namespace mbrt::bench {

std::string toRatioSvg(const Report& report) {
  // Per scene, one bar per structure: rays/s on all threads divided by the
  // reference's (Embree when it ran on the scene, else bvh-interp).
  const double clip = 1.5;
  const int labelW = 110, chartW = 540, barH = 12, gap = 2, sceneGap = 14, top = 40;
  std::ostringstream body;
  int y = top;
  std::string refName = "embree";
  for (const std::string& scene : sceneOrder(report)) {
    const Result* ref = find(report, scene, "embree");
    if (!ref) {
      ref = find(report, scene, "bvh-interp");
      refName = "bvh-interp";
    }
    if (!ref || !(ref->mraysMt > 0)) continue;
    const int first = y;
    for (const Result& r : report.results) {
      if (r.scene != scene || &r == ref) continue;
      const double ratio = r.mraysMt / ref->mraysMt;
      const double w = std::min(ratio, clip) / clip * chartW;
      const char* color = r.accel == "frozen" ? "#888" : ratio >= 1.0 ? "#3a8a4a" : "#3a78b8";
      body << "<rect x='" << labelW << "' y='" << y << "' width='" << fmt(w, 4) << "' height='" << barH << "' fill='"
           << color << "'/><text x='" << fmt(labelW + w + 4, 4) << "' y='" << y + barH - 2 << "' font-size='10'>"
           << escapeXml(r.accel) << " " << fmt(ratio) << "</text>";
      y += barH + gap;
    }
    body << "<text x='4' y='" << (first + y) / 2 + 4 << "' font-size='13' font-weight='bold'>" << escapeXml(scene)
         << "</text>";
    y += sceneGap;
  }
  const double oneX = labelW + chartW / clip;
  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << labelW + chartW + 120 << "' height='" << y
    << "' style='background:#fff'><text x='4' y='16' font-size='14' font-weight='bold'>Rays/s on " << report.threads
    << " threads relative to " << (refName == "embree" ? "Embree" : refName) << " (bars clipped at " << fmt(clip)
    << ")</text><line x1='" << fmt(oneX, 5) << "' y1='" << top - 10 << "' x2='" << fmt(oneX, 5) << "' y2='" << y
    << "' stroke='#000' stroke-dasharray='4,3'/><text x='" << fmt(oneX + 4, 5) << "' y='" << top - 12
    << "' font-size='11'>" << (refName == "embree" ? "Embree" : refName) << " = 1</text>" << body.str() << "</svg>\n";
  return s.str();
}

}  // namespace mbrt::bench
