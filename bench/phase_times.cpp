// Where the default export's time goes, phase by phase, on one thread and on several: each
// phase's single-thread seconds, its speed-up, and the share of the single-thread time that
// runs serially (phases marked serial, and any time in no phase), with the speed-up that share
// allows on 16 cores (Amdahl). base/phase_times.h says how phases are cut.
//   frepcad_phases [--cells N] [--threads 1,2] [--rounds R] [--set NAME=VALUE]... MODEL...
// (examples/MODEL.json; --set: a mesh setting by its table name, e.g. tolerance=0.001 or
// straighten_creases=true, mesh/mesh_settings.h)
// Each thread count is run R times, alternating, and the fastest whole export of each kept.
#include "base/phase_times.h"

#include <tbb/global_control.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "base/process_memory.h"
#include "frep/model_json.h"
#include "pipeline/export_pipeline.h"

namespace {

struct Run {
  double total = 0.0;
  std::vector<frep::PhaseTime> phases;
};

Run exportOnce(const frep::Program& program, const frep::ExportRequest& request,
               const std::string& path, const std::string& name, int threads) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(threads));
  Run run;
  {
    frep::PhaseRecording recording;
    frep::exportField(program, request, path, name);
    run.phases = recording.phases();
  }
  for (const frep::PhaseTime& p : run.phases) run.total += p.seconds;
  return run;
}

double secondsOf(const Run& run, const std::string& name) {
  for (const frep::PhaseTime& p : run.phases)
    if (p.name == name) return p.seconds;
  return 0.0;
}

int usage() {
  std::fprintf(stderr,
               "usage: frepcad_phases [--cells N] [--threads 1,2] [--rounds R] "
               "[--set NAME=VALUE]... MODEL...\n");
  return 2;
}

// A setting's value from its text, as the table's kinds take it.
frep::SettingValue settingValue(const std::string& text) {
  if (text == "true" || text == "false") return text == "true";
  char* end = nullptr;
  const long whole = std::strtol(text.c_str(), &end, 10);
  if (!text.empty() && *end == '\0') return whole;
  const double number = std::strtod(text.c_str(), &end);
  if (!text.empty() && *end == '\0') return number;
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  frep::useLargePageHeap();  // memory taken as frepcad takes it, so the phases are its own
  long cells = 512;
  int rounds = 3;
  std::vector<int> threadCounts{1, 2};
  std::vector<std::string> models;
  frep::MeshSettings settings;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc) {
      const std::string v = argv[++i];
      const std::size_t eq = v.find('=');
      if (eq == std::string::npos) return usage();
      try {
        frep::setMeshSetting(settings, v.substr(0, eq), settingValue(v.substr(eq + 1)));
        settings.validate();
      } catch (const std::exception& e) {
        std::fprintf(stderr, "frepcad_phases: %s\n", e.what());
        return 2;
      }
    } else if ((a == "--cells" || a == "--rounds" || a == "--threads") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (a == "--cells") cells = std::atol(v.c_str());
      if (a == "--rounds") rounds = std::atoi(v.c_str());
      if (a == "--threads") {
        threadCounts.clear();
        std::stringstream in(v);
        for (std::string t; std::getline(in, t, ',');) threadCounts.push_back(std::atoi(t.c_str()));
      }
    } else if (!a.empty() && a[0] != '-') {
      models.push_back(a);
    } else {
      return usage();
    }
  }
  if (models.empty() || cells < 2 || rounds < 1 || threadCounts.empty() || threadCounts[0] != 1)
    return usage();  // (the first count must be 1: shares are of the single-thread time)

  const std::string path =
      (std::filesystem::exists("/dev/shm") ? std::string("/dev/shm") : std::string("/tmp")) +
      "/frepcad-phases-" + std::to_string(getpid()) + ".stl";
  for (const std::string& name : models) {
    const frep::Model m =
        frep::loadModel(std::string(FREP_SOURCE_DIR) + "/examples/" + name + ".json");
    const frep::Program program = frep::compile(m.root);
    frep::ExportRequest request;
    request.mesh = settings;
    request.box.bbox = *m.bbox;
    double longest = 0.0;
    for (int a = 0; a < 3; ++a) longest = std::max(longest, m.bbox->hi[a] - m.bbox->lo[a]);
    request.box.resolution = longest / static_cast<double>(cells);

    std::map<int, Run> best;
    for (int r = 0; r < rounds; ++r)
      for (int t : threadCounts) {
        Run run = exportOnce(program, request, path, name, t);
        if (!best.count(t) || run.total < best[t].total) best[t] = std::move(run);
      }
    std::filesystem::remove(path);

    const Run& one = best[1];
    std::printf("\n%s at %ld cells (fastest of %d rounds each)\n\n", name.c_str(), cells, rounds);
    std::printf("| phase | kind | 1 thread s | share |");
    for (std::size_t k = 1; k < threadCounts.size(); ++k)
      std::printf(" %d threads s | speed-up |", threadCounts[k]);
    std::printf("\n|---|---|---|---|");
    for (std::size_t k = 1; k < threadCounts.size(); ++k) std::printf("---|---|");
    std::printf("\n");
    double serial = 0.0;
    for (const frep::PhaseTime& p : one.phases) {
      const bool isSerial = p.kind == frep::PhaseKind::Serial;
      if (isSerial) serial += p.seconds;
      std::printf("| %s | %s | %.4f | %.1f %% |", p.name.c_str(), isSerial ? "serial" : "parallel",
                  p.seconds, 100.0 * p.seconds / one.total);
      for (std::size_t k = 1; k < threadCounts.size(); ++k) {
        const double s = secondsOf(best[threadCounts[k]], p.name);
        std::printf(" %.4f | %.2fx |", s, s > 0.0 ? p.seconds / s : 0.0);
      }
      std::printf("\n");
    }
    std::printf("| **whole export** | | %.4f | 100 %% |", one.total);
    for (std::size_t k = 1; k < threadCounts.size(); ++k) {
      const double s = best[threadCounts[k]].total;
      std::printf(" %.4f | %.2fx |", s, one.total / s);
    }
    const double share = serial / one.total;
    std::printf("\n\nserial share %.1f %% of the single-thread time: at most %.1fx on 16 cores\n",
                100.0 * share, 1.0 / (share + (1.0 - share) / 16.0));
  }
  return 0;
}
