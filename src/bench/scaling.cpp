// `mbrt bench --scaling`: the same scenes at several sizes, each structure's
// build time, memory and secondary rays/s against the primitive count, so
// that a kind whose cost grows faster than N log N shows it.
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "mbrt/bench.h"
#include "bench/report_util.h"

namespace mbrt::bench {

std::vector<std::string> scalingDefaultAccels() {
  std::vector<std::string> names;
  const auto kinds = availableAccelKinds();
  for (AccelKind k : {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Stbvh, AccelKind::Msbvh,
                      AccelKind::Embree})
    if (std::find(kinds.begin(), kinds.end(), k) != kinds.end()) names.push_back(std::string(toString(k)));
  return names;
}

ScalingReport runScaling(const ScalingOptions& options) {
  ScalingReport out;
  for (double size : options.sizes) {
    Options o = options.bench;
    o.size = size;
    o.scenes = options.scenes;
    o.accels = options.accels.empty() ? scalingDefaultAccels() : options.accels;
    o.secondaryOnly = true;
    const Report r = run(o);
    out.cpu = r.cpu;
    out.commit = r.commit;
    out.threads = r.threads;
    for (const Result& x : r.results)
      out.rows.push_back({x.scene, x.accel, size, x.primitives, x.buildS, x.bytes, x.set(RaySet::Secondary).mraysMt});
    for (const std::string& n : r.notes) out.notes.push_back("size " + fmt(size) + ": " + n);
  }
  // Scene by scene as given, then structure by structure, sizes ascending.
  auto sceneAt = [&](const std::string& s) {
    return std::find(options.scenes.begin(), options.scenes.end(), s) - options.scenes.begin();
  };
  std::stable_sort(out.rows.begin(), out.rows.end(), [&](const ScalingRow& a, const ScalingRow& b) {
    if (a.scene != b.scene) return sceneAt(a.scene) < sceneAt(b.scene);
    return a.accel != b.accel ? a.accel < b.accel : a.size < b.size;
  });
  return out;
}

namespace {

// log(b/a) / log(nb/na): 1 is linear in the primitive count.
std::string growth(double a, double b, size_t na, size_t nb) {
  if (!(a > 0) || !(b > 0) || na == 0 || nb <= na) return "–";
  return fmt(std::log(b / a) / std::log(double(nb) / double(na)));
}

}  // namespace

std::string toMarkdown(const ScalingReport& report) {
  std::ostringstream out;
  out << "mbrt bench --scaling — " << report.cpu << ", " << report.threads << " threads, commit " << report.commit
      << "\n\nSecondary rays on all threads. Growth: the exponent of the primitive count from the size before"
         " (1 = linear, N log N a little above 1).\n\n";
  out << "| scene | accel | size | primitives | build s | build growth | MB | bytes/prim | Mrays/s | Mrays/s growth |\n";
  out << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  const ScalingRow* prev = nullptr;
  for (const ScalingRow& r : report.rows) {
    const bool same = prev && prev->scene == r.scene && prev->accel == r.accel;
    out << "| " << r.scene << " | " << r.accel << " | " << fmt(r.size) << " | " << r.primitives << " | "
        << fmt(r.buildS) << " | " << (same ? growth(prev->buildS, r.buildS, prev->primitives, r.primitives) : "–")
        << " | " << fmt(double(r.bytes) / 1e6) << " | "
        << (r.primitives ? fmt(double(r.bytes) / double(r.primitives)) : "–") << " | " << fmt(r.mraysMt) << " | "
        << (same ? growth(prev->mraysMt, r.mraysMt, prev->primitives, r.primitives) : "–") << " |\n";
    prev = &r;
  }
  if (!report.notes.empty()) {
    out << "\nNotes:\n";
    for (const std::string& n : report.notes) out << "- " << n << "\n";
  }
  return out.str();
}

std::string toJson(const ScalingReport& report) {
  std::ostringstream o;
  o << "{\n  \"machine\": {\"cpu\": " << jsonString(report.cpu) << ", \"threads\": " << report.threads
    << ", \"commit\": " << jsonString(report.commit) << "},\n  \"rows\": [";
  for (size_t i = 0; i < report.rows.size(); ++i) {
    const ScalingRow& r = report.rows[i];
    o << (i ? ",\n    " : "\n    ") << "{\"scene\": " << jsonString(r.scene) << ", \"accel\": " << jsonString(r.accel)
      << ", \"size\": " << jsonNum(r.size) << ", \"primitives\": " << r.primitives
      << ", \"build_s\": " << jsonNum(r.buildS) << ", \"bytes\": " << r.bytes
      << ", \"mrays_mt\": " << jsonNum(r.mraysMt) << "}";
  }
  o << "\n  ],\n  \"notes\": [";
  for (size_t i = 0; i < report.notes.size(); ++i) o << (i ? ", " : "") << jsonString(report.notes[i]);
  o << "]\n}\n";
  return o.str();
}

std::string toSvg(const ScalingReport& report) {
  // Three log-log panels against the primitive count: build seconds, MB and
  // Mrays/s; one line per scene and structure.
  struct Panel {
    const char* title;
    double (*value)(const ScalingRow&);
  };
  const Panel panels[3] = {{"build s", [](const ScalingRow& r) { return r.buildS; }},
                           {"MB", [](const ScalingRow& r) { return double(r.bytes) / 1e6; }},
                           {"Mrays/s (secondary)", [](const ScalingRow& r) { return r.mraysMt; }}};
  const char* colors[] = {"#3a78b8", "#d08030", "#3a8a4a", "#a03a8a", "#888", "#b83a3a", "#3ab8b0", "#7a6a2a"};
  const int pw = 300, ph = 220, pad = 46, top = 30;
  std::map<std::string, int> colorOf;
  for (const ScalingRow& r : report.rows) colorOf.emplace(r.accel, int(colorOf.size()) % 8);
  std::ostringstream s;
  const int width = 3 * (pw + pad) + 20, height = top + ph + pad + 20 + 16 * int(colorOf.size());
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
    << "' style='background:#fff'><text x='4' y='16' font-size='14' font-weight='bold'>Cost against size ("
    << report.threads << " threads; solid: first scene, dashed: others)</text>";
  double nLo = 1e300, nHi = 0;
  for (const ScalingRow& r : report.rows)
    if (r.primitives) nLo = std::min(nLo, double(r.primitives)), nHi = std::max(nHi, double(r.primitives));
  if (nHi <= nLo) nHi = nLo * 10;
  for (int p = 0; p < 3; ++p) {
    const int x0 = pad + p * (pw + pad);
    double lo = 1e300, hi = 0;
    for (const ScalingRow& r : report.rows)
      if (panels[p].value(r) > 0) lo = std::min(lo, panels[p].value(r)), hi = std::max(hi, panels[p].value(r));
    if (!(hi > 0)) continue;
    if (hi <= lo) hi = lo * 10;
    auto X = [&](double n) { return x0 + pw * std::log(n / nLo) / std::log(nHi / nLo); };
    auto Y = [&](double v) { return top + ph - ph * std::log(v / lo) / std::log(hi / lo); };
    s << "<rect x='" << x0 << "' y='" << top << "' width='" << pw << "' height='" << ph
      << "' fill='none' stroke='#ccc'/><text x='" << x0 << "' y='" << top - 4 << "' font-size='12'>"
      << panels[p].title << " (" << fmt(lo) << " – " << fmt(hi) << ")</text><text x='" << x0 << "' y='"
      << top + ph + 14 << "' font-size='10'>" << fmt(nLo) << " … " << fmt(nHi) << " primitives</text>";
    const std::string firstScene = report.rows.empty() ? "" : report.rows.front().scene;
    for (size_t i = 0; i < report.rows.size();) {
      size_t j = i;
      std::ostringstream pts;
      for (; j < report.rows.size() && report.rows[j].scene == report.rows[i].scene &&
             report.rows[j].accel == report.rows[i].accel;
           ++j)
        if (panels[p].value(report.rows[j]) > 0 && report.rows[j].primitives)
          pts << fmt(X(double(report.rows[j].primitives)), 5) << "," << fmt(Y(panels[p].value(report.rows[j])), 5)
              << " ";
      s << "<polyline fill='none' stroke-width='2' stroke='" << colors[colorOf[report.rows[i].accel]] << "'"
        << (report.rows[i].scene == firstScene ? "" : " stroke-dasharray='5,3'") << " points='" << pts.str()
        << "'/>";
      i = j;
    }
  }
  int y = top + ph + pad;
  for (const auto& [name, c] : colorOf) {
    s << "<rect x='" << pad << "' y='" << y - 9 << "' width='14' height='4' fill='" << colors[c] << "'/><text x='"
      << pad + 20 << "' y='" << y - 4 << "' font-size='11'>" << escapeXml(name) << "</text>";
    y += 16;
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace mbrt::bench
