// The bench's charts: an HTML page of SVG bar charts, one SVG of every
// structure's secondary rays/s relative to Embree, and the scaling chart.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "mbrt/bench.h"
#include "bench/report_util.h"

namespace mbrt::bench {
namespace {

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
      speed.push_back({r.accel, r.set(r.mainSet()).mraysMt});
      build.push_back({r.accel, r.buildS});
    }
    o << "<h2>" << escapeXml(scene) << "</h2><div class='row'>" << barChart("memory", mem, "MB")
      << barChart("secondary (frozen rows: frozen set) rays/s, all threads", speed, "Mrays/s") << barChart("build time", build, "s") << "</div>";
  }
  o << "<pre>" << escapeXml(toMarkdown(report)) << "</pre></body></html>\n";
  return o.str();
}

std::string toRatioSvg(const Report& report) {
  // Per scene, one bar per structure: secondary rays/s on all threads
  // divided by the reference's (Embree's default mode when it ran on the
  // scene, else bvh-interp); frozen rows: frozen set over embree-static.
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
    if (!ref || !(ref->set(RaySet::Secondary).mraysMt > 0)) continue;
    const Result* staticRef = find(report, scene, "embree-static");
    const int first = y;
    for (const Result& r : report.results) {
      if (r.scene != scene || &r == ref) continue;
      const Result* base = r.frozen ? staticRef : ref;
      const RaySet set = r.mainSet();
      if (!base || base == &r || !(base->set(set).mraysMt > 0)) continue;
      const double ratio = r.set(set).mraysMt / base->set(set).mraysMt;
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
    << "' style='background:#fff'><text x='4' y='16' font-size='14' font-weight='bold'>Secondary rays/s on " << report.threads
    << " threads relative to " << (refName == "embree" ? "Embree" : refName) << " (bars clipped at " << fmt(clip)
    << ")</text><line x1='" << fmt(oneX, 5) << "' y1='" << top - 10 << "' x2='" << fmt(oneX, 5) << "' y2='" << y
    << "' stroke='#000' stroke-dasharray='4,3'/><text x='" << fmt(oneX + 4, 5) << "' y='" << top - 12
    << "' font-size='11'>" << (refName == "embree" ? "Embree" : refName) << " = 1</text>" << body.str() << "</svg>\n";
  return s.str();
}

}  // namespace mbrt::bench
