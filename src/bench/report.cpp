// The benchmark's tables: markdown (per scene, then the geometric means) and
// JSON, and the best-kind and geometric-mean figures they print.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "mbrt/bench.h"
#include "bench/report_util.h"

namespace mbrt::bench {

const Result* bestMbrt(const Report& report, const std::string& scene, RaySet set, bool singleKinds) {
  const Result* best = nullptr;
  for (const Result& r : report.results) {
    if (r.scene != scene || r.peer || r.frozen != (set == RaySet::Frozen)) continue;
    if (singleKinds && r.accel == "auto") continue;  // auto combines kinds
    const SetResult& s = r.set(set);
    if (!s.traced || !(s.mraysMt > 0)) continue;
    if (!best || s.mraysMt > best->set(set).mraysMt) best = &r;
  }
  return best;
}

std::vector<Geomean> geomeans(const Report& report) {
  std::vector<Geomean> out;
  for (RaySet set : kAllRaySets) {
    const std::vector<std::string> peers =
        set == RaySet::Frozen ? std::vector<std::string>{"embree-static", "embree-static-robust"}
                              : std::vector<std::string>{"embree", "embree-robust"};
    for (const std::string& peer : peers) {
      Geomean g{set, peer, 0.0, 0};
      double logSum = 0.0;
      for (const std::string& scene : sceneOrder(report)) {
        const Result* best = bestMbrt(report, scene, set);
        const Result* p = find(report, scene, peer);
        if (!best || !p || !p->set(set).traced || !(p->set(set).mraysMt > 0)) continue;
        logSum += std::log(best->set(set).mraysMt / p->set(set).mraysMt);
        ++g.scenes;
      }
      if (g.scenes == 0) continue;
      g.value = std::exp(logSum / g.scenes);
      out.push_back(g);
    }
  }
  return out;
}

namespace {

std::string percent(double v) { return fmt(100.0 * v, 3) + "%"; }

std::string setLine(const SceneInfo& info) {
  auto one = [&](RaySet s, const char* what) {
    const SetInfo& x = info.sets[size_t(s)];
    return std::string(toString(s)) + " " + std::to_string(x.rays) + " (" + what + " " + percent(x.hitRate) + ")";
  };
  std::string line = "Rays: " + one(RaySet::Primary, "hit") + ", " + one(RaySet::Secondary, "hit");
  if (info.bounces + info.inward > 0)
    line += " = " + std::to_string(info.bounces) + " bounces + " + std::to_string(info.inward) + " from around";
  line += ", " + one(RaySet::Shadow, "occluded") + ", " + one(RaySet::Frozen, "hit") + ", " +
          one(RaySet::Incoherent, "hit") + ".";
  return line;
}

std::string setMt(const Result& r, RaySet s) { return r.set(s).traced ? fmt(r.set(s).mraysMt) : "–"; }

std::string setRatio(const Result& r, const Result* base, RaySet s) {
  if (!base || !r.set(s).traced || !base->set(s).traced || !(base->set(s).mraysMt > 0)) return "–";
  return fmt(r.set(s).mraysMt / base->set(s).mraysMt);
}

std::string mismatchText(const Result& r) {
  size_t brute = 0, checked = 0, embree = 0;
  bool anyEmbree = false;
  for (const SetResult& s : r.sets) {
    brute += s.mismatchesBrute;
    checked += s.bruteChecked;
    if (s.mismatchesEmbree) {
      anyEmbree = true;
      embree += *s.mismatchesEmbree;
    }
  }
  std::string m = std::to_string(brute) + "/" + std::to_string(checked) + " brute";
  if (anyEmbree) m += ", " + std::to_string(embree) + " embree-robust";
  return m;
}

void sceneTable(std::ostringstream& out, const Report& report, const SceneInfo& info) {
  const std::string& scene = info.name;
  const Result* embree = find(report, scene, "embree");
  const Result* robust = find(report, scene, "embree-robust");
  const Result* estatic = find(report, scene, "embree-static");
  const Result* estaticRobust = find(report, scene, "embree-static-robust");
  // The headline set's size in the title, the others in the line below.
  out << "\n### " << scene << " (" << info.primitives << " primitives, " << info.sets[size_t(RaySet::Secondary)].rays
      << " rays)\n\n"
      << setLine(info) << "\n\n";
  out << "| accel | build s | Mprims/s | MB | peak MB | SAH | steps | box tests | isects | primary Mrays/s"
         " | secondary Mrays/s 1t | secondary Mrays/s mt | shadow Mrays/s | sec ÷ embree | sec ÷ embree-robust"
         " | mem ÷ embree | build ÷ embree | frozen set Mrays/s | frozen ÷ embree-static"
         " | frozen ÷ embree-static-robust | incoherent Mrays/s | inc ÷ embree | mismatches |\n";
  out << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Result& r : report.results) {
    if (r.scene != scene) continue;
    const SetResult& sec = r.set(RaySet::Secondary);
    out << "| " << r.accel << " | " << fmt(r.buildS) << " | " << fmt(r.buildMprims) << " | "
        << fmt(double(r.bytes) / 1e6) << " | " << fmt(double(r.peakBuildBytes) / 1e6) << " | " << opt(r.sah)
        << " | " << opt(r.stepsMean) << " | " << opt(r.boxTestsMean) << " | " << opt(r.isectsMean) << " | "
        << setMt(r, RaySet::Primary) << " | " << (sec.traced ? fmt(sec.mraysSt) : "–") << " | "
        << setMt(r, RaySet::Secondary) << " | " << setMt(r, RaySet::Shadow) << " | "
        << setRatio(r, embree, RaySet::Secondary) << " | " << setRatio(r, robust, RaySet::Secondary) << " | "
        << (embree && embree->bytes ? fmt(double(r.bytes) / double(embree->bytes)) : "–") << " | "
        << (embree && embree->buildS > 0 ? fmt(r.buildS / embree->buildS) : "–") << " | "
        << setMt(r, RaySet::Frozen) << " | " << setRatio(r, estatic, RaySet::Frozen) << " | "
        << setRatio(r, estaticRobust, RaySet::Frozen) << " | " << setMt(r, RaySet::Incoherent) << " | "
        << setRatio(r, embree, RaySet::Incoherent) << " | " << mismatchText(r) << " |\n";
  }
  if (const Result* best = bestMbrt(report, scene, RaySet::Secondary))
    out << "\nBest mbrt kind on the secondary set: `" << best->accel << "`.\n";
  const Result* single = bestMbrt(report, scene, RaySet::Secondary, true);
  if (const Result* a = find(report, scene, "auto"); a && single && single->bytes && single->buildS > 0)
    out << "\n`auto` ÷ the best single kind (`" << single->accel << "`): secondary rays/s "
        << setRatio(*a, single, RaySet::Secondary) << ", memory " << fmt(double(a->bytes) / double(single->bytes))
        << ", build time " << fmt(a->buildS / single->buildS) << ".\n";
  for (const Result& r : report.results) {
    std::string cut;
    for (RaySet s : kAllRaySets)
      if (r.scene == scene && r.set(s).traced && r.set(s).timedRays < r.set(s).rays)
        cut += std::string(cut.empty() ? "" : ", ") + std::to_string(r.set(s).timedRays) + " of the " +
               std::to_string(r.set(s).rays) + " " + std::string(toString(s)) + " rays";
    if (!cut.empty())
      out << "\n`" << r.accel << "` was timed on " << cut
          << ", evenly spread over each set (its full passes would exceed the time budget).\n";
  }
  for (const Result& r : report.results) {
    const size_t full = std::min(report.options.countSample, r.set(r.mainSet()).rays);
    if (r.scene == scene && r.countedRays > 0 && r.countedRays < full)
      out << "\n`" << r.accel << "`'s counters are over " << r.countedRays << " of the " << full
          << " sampled rays (counting them all would exceed its time budget).\n";
  }
}

}  // namespace

std::string toMarkdown(const Report& report) {
  std::ostringstream out;
  out << "mbrt bench — " << report.cpu << ", " << report.threads << " threads, commit " << report.commit << "\n";
  for (const SceneInfo& info : report.scenes) sceneTable(out, report, info);
  const std::vector<Geomean> gms = geomeans(report);
  if (!gms.empty()) {
    out << "\n### Geometric mean over scenes: best mbrt kind ÷ Embree (rays/s, all threads)\n\n";
    out << "| set | ÷ embree | ÷ embree-robust | ÷ embree-static | ÷ embree-static-robust | scenes |\n"
           "|---|---:|---:|---:|---:|---:|\n";
    for (RaySet set : kAllRaySets) {
      std::string cells[4] = {"–", "–", "–", "–"};
      int scenes = 0;
      for (const Geomean& g : gms) {
        if (g.set != set) continue;
        const int col = g.peer == "embree" ? 0 : g.peer == "embree-robust" ? 1 : g.peer == "embree-static" ? 2 : 3;
        cells[col] = fmt(g.value);
        scenes = std::max(scenes, g.scenes);
      }
      if (scenes == 0) continue;
      out << "| " << toString(set) << (set == RaySet::Secondary ? " (headline)" : "")
          << (set == RaySet::Frozen ? " (`frozen`)" : "") << " | " << cells[0] << " | " << cells[1] << " | "
          << cells[2] << " | " << cells[3] << " | " << scenes << " |\n";
    }
  }
  if (!report.notes.empty()) {
    out << "\nNotes:\n";
    for (const std::string& n : report.notes) out << "- " << n << "\n";
  }
  out << "\n`frozen`, `embree-static` and `embree-static-robust`: build and memory per structure ("
      << report.options.frozenTimes
      << " frozen times); they trace the frozen set only. `embree` and `embree-static` run with Embree's default"
         " flags, `embree-robust` and `embree-static-robust` with RTC_SCENE_FLAG_ROBUST (watertight, as every"
         " mbrt kind). Embree exposes no tree: SAH and counters n/a.\n";
  return out.str();
}

namespace {

std::string jsonSet(const SetResult& s) {
  std::ostringstream o;
  o << "{\"traced\": " << (s.traced ? "true" : "false") << ", \"rays\": " << s.rays
    << ", \"timed_rays\": " << s.timedRays << ", \"mrays_st\": " << jsonNum(s.mraysSt)
    << ", \"mrays_mt\": " << jsonNum(s.mraysMt) << ", \"mismatches_brute\": " << s.mismatchesBrute
    << ", \"brute_checked\": " << s.bruteChecked << ", \"mismatches_embree_robust\": " << jsonOpt(s.mismatchesEmbree)
    << "}";
  return o.str();
}

void jsonResult(std::ostringstream& o, const Result& r) {
  o << "{\"scene\": " << jsonString(r.scene) << ", \"accel\": " << jsonString(r.accel)
    << ", \"frozen\": " << (r.frozen ? "true" : "false") << ", \"peer\": " << (r.peer ? "true" : "false")
    << ", \"primitives\": " << r.primitives << ", \"build_s\": " << jsonNum(r.buildS)
    << ", \"build_mprims\": " << jsonNum(r.buildMprims) << ", \"builds\": " << r.builds << ", \"bytes\": " << r.bytes
    << ", \"peak_build_bytes\": " << r.peakBuildBytes << ", \"sah\": " << jsonOpt(r.sah)
    << ", \"steps_mean\": " << jsonOpt(r.stepsMean) << ", \"steps_max\": " << jsonOpt(r.stepsMax)
    << ", \"box_tests_mean\": " << jsonOpt(r.boxTestsMean) << ", \"isects_mean\": " << jsonOpt(r.isectsMean)
    << ", \"isects_max\": " << jsonOpt(r.isectsMax) << ", \"counted_rays\": " << r.countedRays
    << ", \"mismatches\": " << r.mismatches() << ", \"sets\": {";
  for (RaySet s : kAllRaySets)
    o << (s == RaySet::Primary ? "" : ", ") << jsonString(std::string(toString(s))) << ": " << jsonSet(r.set(s));
  o << "}}";
}

}  // namespace

std::string toJson(const Report& report) {
  std::ostringstream o;
  o << "{\n  \"machine\": {\"cpu\": " << jsonString(report.cpu) << ", \"threads\": " << report.threads
    << ", \"commit\": " << jsonString(report.commit) << "},\n";
  o << "  \"options\": {\"size\": " << jsonNum(report.options.size) << ", \"width\": " << report.options.width
    << ", \"height\": " << report.options.height << ", \"frozen_times\": " << report.options.frozenTimes
    << ", \"repeats\": " << report.options.repeats << ", \"seed\": " << report.options.seed << "},\n";
  o << "  \"scenes\": [";
  for (size_t i = 0; i < report.scenes.size(); ++i) {
    const SceneInfo& s = report.scenes[i];
    o << (i ? ",\n" : "\n") << "    {\"scene\": " << jsonString(s.name) << ", \"primitives\": " << s.primitives
      << ", \"bounces\": " << s.bounces << ", \"inward\": " << s.inward << ", \"sets\": {";
    for (RaySet set : kAllRaySets)
      o << (set == RaySet::Primary ? "" : ", ") << jsonString(std::string(toString(set))) << ": {\"rays\": "
        << s.sets[size_t(set)].rays << ", \"hit_rate\": " << jsonNum(s.sets[size_t(set)].hitRate) << "}";
    o << "}}";
  }
  o << "\n  ],\n  \"results\": [";
  for (size_t i = 0; i < report.results.size(); ++i) {
    o << (i ? ",\n    " : "\n    ");
    jsonResult(o, report.results[i]);
  }
  o << "\n  ],\n  \"geomeans\": [";
  const std::vector<Geomean> gms = geomeans(report);
  for (size_t i = 0; i < gms.size(); ++i)
    o << (i ? ", " : "") << "{\"set\": " << jsonString(std::string(toString(gms[i].set)))
      << ", \"peer\": " << jsonString(gms[i].peer) << ", \"value\": " << jsonNum(gms[i].value)
      << ", \"scenes\": " << gms[i].scenes << "}";
  o << "],\n  \"notes\": [";
  for (size_t i = 0; i < report.notes.size(); ++i) o << (i ? ", " : "") << jsonString(report.notes[i]);
  o << "]\n}\n";
  return o.str();
}

}  // namespace mbrt::bench
