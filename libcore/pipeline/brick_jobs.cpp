#include "pipeline/brick_jobs.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

#include "base/errors.h"
#include "base/progress.h"
#include "check/partitioned_check.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"
#include "io/mesh_piece_file.h"
#include "io/stl_stream.h"
#include "io/three_mf_stream.h"
#include "mesh/piece_merge.h"

namespace frep {

MeshingOptions brickMeshingOptions(const BrickJobPlan& plan) {
  MeshingOptions o;
  o.bbox = plan.box.box;
  o.resolution = plan.box.resolution;
  o.settings = plan.mesh;
  o.normals = false;
  // (a piece carries no stats: brick jobs do not report thin parts yet)
  o.findThinParts = false;
  return o;
}

namespace {

void mix(std::uint64_t& h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ull;
  }
}

}  // namespace

std::uint64_t textFingerprint(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  mix(h, text.data(), text.size());
  return h;
}

void checkBrickJobSettings(const MeshSettings& settings) {
  // (the simplifier and the straightening work on the whole mesh; a job's refined cubes
  // would change its neighbours' faces)
  for (const char* option : {"refine", "straighten_creases", "tolerance"})
    if (getMeshSetting(settings, option) != getMeshSetting(MeshSettings{}, option))
      throw SettingError(option, std::string("brick jobs cannot be combined with {") + option +
                                     "} yet: leave it at " +
                                     settingText(getMeshSetting(MeshSettings{}, option)));
}

BrickJobPlan planBrickJobs(const MeshingBox& box, const MeshSettings& settings, std::uint32_t jobs,
                           std::uint64_t model) {
  settings.validate();
  checkBrickJobSettings(settings);
  if (jobs < 1 || jobs > kMaxBrickJobs)
    throw ModelError("bricks: the number of brick jobs must be 1 to " +
                     std::to_string(kMaxBrickJobs) + ", got " + std::to_string(jobs));
  BrickJobPlan plan;
  plan.box = box;
  plan.mesh = settings;
  plan.jobs = jobs;
  brickGrid(brickMeshingOptions(plan), plan.bricks);
  // the job count's prime factors, largest first, each to the axis with the most bricks per
  // job that can still take it
  std::vector<std::uint32_t> primes;
  for (std::uint32_t n = jobs, f = 2; n > 1;) {
    if (f * f > n) {
      primes.push_back(n);
      break;
    }
    if (n % f == 0) {
      primes.push_back(f);
      n /= f;
    } else {
      ++f;
    }
  }
  std::sort(primes.rbegin(), primes.rend());
  for (std::uint32_t p : primes) {
    int best = -1;
    for (int a = 0; a < 3; ++a) {
      if (plan.split[a] * p > plan.bricks[a]) continue;
      if (best < 0 || plan.bricks[a] * plan.split[best] > plan.bricks[best] * plan.split[a])
        best = a;
    }
    if (best < 0) {
      std::ostringstream os;
      os << "bricks: " << jobs << " jobs cannot be cut from the mesher's " << plan.bricks[0]
         << " x " << plan.bricks[1] << " x " << plan.bricks[2]
         << " bricks (a job holds whole bricks of 16 cells): use fewer jobs or finer cells";
      throw ModelError(os.str());
    }
    plan.split[best] *= p;
  }
  std::uint64_t h = model;
  const double numbers[7] = {box.box.lo[0], box.box.lo[1], box.box.lo[2], box.box.hi[0],
                             box.box.hi[1], box.box.hi[2], box.resolution};
  mix(h, numbers, sizeof(numbers));
  const std::uint32_t flags[4] = {settings.sharpFeatures ? 1u : 0u,
                                  static_cast<std::uint32_t>(settings.mesher), jobs,
                                  settings.dropFlatVertices ? 1u : 0u};
  mix(h, flags, sizeof(flags));
  plan.runId = h;
  return plan;
}

void jobBricks(const BrickJobPlan& plan, std::uint32_t job, std::int64_t lo[3],
               std::int64_t hi[3]) {
  if (job >= plan.jobs)
    throw ModelError("bricks: job " + std::to_string(job) + " of a run of " +
                     std::to_string(plan.jobs) + " jobs (numbered from 0)");
  std::int64_t at[3] = {job % plan.split[0], (job / plan.split[0]) % plan.split[1],
                        job / (plan.split[0] * plan.split[1])};
  for (int a = 0; a < 3; ++a) {
    lo[a] = at[a] * plan.bricks[a] / plan.split[a];
    hi[a] = (at[a] + 1) * plan.bricks[a] / plan.split[a];
  }
}

MeshPiece runBrickJob(const Field& field, const BrickJobPlan& plan, std::uint32_t job,
                      const std::function<bool(double)>& progress) {
  std::int64_t lo[3], hi[3];
  jobBricks(plan, job, lo, hi);
  MeshingOptions o = brickMeshingOptions(plan);
  o.progress = progress;
  MeshPiece piece = polygonizePiece(field, o, lo, hi);
  piece.runId = plan.runId;
  piece.job = job;
  piece.jobs = plan.jobs;
  return piece;
}

namespace {

// The box of a job's vertices in model units: its cells' grid points, widened by a cell on
// every side, so that a crease flip the merge made across a job's face (a triangle reaching
// one cell into the neighbour) stays in the box of the job it is given to.
std::vector<Box3> jobBoxes(const BrickJobPlan& plan, const std::int64_t gridCells[3]) {
  std::vector<Box3> boxes(plan.jobs);
  const int bc = brickMeshingOptions(plan).brickCells;
  for (std::uint32_t j = 0; j < plan.jobs; ++j) {
    std::int64_t lo[3], hi[3];
    jobBricks(plan, j, lo, hi);
    for (int a = 0; a < 3; ++a) {
      const double from = plan.box.box.lo[a], to = plan.box.box.hi[a];
      const double h = (to - from) / static_cast<double>(gridCells[a] - 1);
      const std::int64_t cellLo = lo[a] * bc, cellHi = std::min(hi[a] * bc, gridCells[a]);
      boxes[j].lo[a] = from + (static_cast<double>(cellLo) - 1.5) * h;
      boxes[j].hi[a] = from + (static_cast<double>(cellHi) + 0.5) * h;
    }
  }
  return boxes;
}

std::vector<char> readBytes(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw FileError(file + ": cannot open the check summary");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

MeshPiece readRunPiece(const BrickJobPlan& plan, const std::string& file) {
  MeshPiece piece = readPieceFile(file);
  if (piece.runId != plan.runId)
    throw FileError(file + ": a piece of another run (model, box, options or job count)");
  return piece;
}

}  // namespace

TriangleMesh pieceCheckedPart(const MeshPiece& piece) {
  TriangleMesh m;
  m.positions = piece.positions;
  std::vector<char> left(piece.triangles.size(), 0);
  for (std::uint32_t t : piece.pendingFlips) left.at(t) = 1;
  m.triangles.reserve(piece.triangles.size());
  for (std::size_t t = 0; t < piece.triangles.size(); ++t)
    if (!left[t]) m.triangles.push_back(piece.triangles[t]);
  return m;
}

// A job's check summary starts with the run's id and the job, so a summary is only ever
// taken with its own piece.
constexpr char kJudgedMagic[8] = {'F', 'R', 'E', 'P', 'C', 'H', 'K', '1'};
constexpr std::size_t kJudgedHeader = 8 + 8 + 4;

std::vector<char> judgeBrickPiece(const BrickJobPlan& plan, const MeshPiece& piece) {
  const std::vector<char> judged = PartitionedCheck::judgePart(jobBoxes(plan, piece.gridCells),
                                                               piece.job, pieceCheckedPart(piece));
  std::vector<char> out(kJudgedMagic, kJudgedMagic + 8);
  out.resize(kJudgedHeader);
  std::memcpy(out.data() + 8, &plan.runId, 8);
  std::memcpy(out.data() + 16, &piece.job, 4);
  out.insert(out.end(), judged.begin(), judged.end());
  return out;
}

namespace {

// A job's summary, checked to be of this run and this job, without its header.
std::vector<char> readJudged(const BrickJobPlan& plan, std::uint32_t job, const std::string& file) {
  std::vector<char> bytes = readBytes(file);
  std::uint64_t run = 0;
  std::uint32_t of = 0;
  if (bytes.size() < kJudgedHeader || std::memcmp(bytes.data(), kJudgedMagic, 8) != 0)
    throw FileError(file + ": not a brick job's check summary");
  std::memcpy(&run, bytes.data() + 8, 8);
  std::memcpy(&of, bytes.data() + 16, 4);
  if (run != plan.runId || of != job)
    throw FileError(file + ": the check summary of another run or job (job " + std::to_string(of) +
                    ", expected " + std::to_string(job) + ")");
  bytes.erase(bytes.begin(), bytes.begin() + kJudgedHeader);
  return bytes;
}

}  // namespace

ExportResult exportPieces(const BrickJobPlan& plan, const std::vector<std::string>& pieceFiles,
                          const ExportRequest& request, const std::string& path,
                          const std::vector<std::string>& summaryFiles) {
  using Clock = std::chrono::steady_clock;
  auto report = [&](ExportStage s, double f) {
    if (request.progress && !request.progress(s, f)) throw Cancelled();
  };
  auto since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  const MeshFormat format = request.format ? *request.format : formatFromPath(path);
  if (pieceFiles.size() != plan.jobs)
    throw ModelError("bricks: the run has " + std::to_string(plan.jobs) + " jobs but " +
                     std::to_string(pieceFiles.size()) + " piece files were given");
  if (!summaryFiles.empty() && summaryFiles.size() != pieceFiles.size())
    throw ModelError("bricks: one check summary per piece file, or none");
  ExportResult result;
  result.box = plan.box;
  const double count = static_cast<double>(pieceFiles.size());

  // The whole mesh in memory: each piece read, welded in and dropped.
  auto mergeInMemory = [&](bool withProgress) {
    PieceMerger::MeshCollector sink;
    PieceMerger merger(sink);
    for (std::size_t i = 0; i < pieceFiles.size(); ++i) {
      merger.add(readRunPiece(plan, pieceFiles[i]));
      if (withProgress) report(ExportStage::Mesh, static_cast<double>(i + 1) / count);
    }
    merger.finish();
    return std::move(sink.mesh);
  };

  if (format == MeshFormat::StlBinary || format == MeshFormat::ThreeMf) {
    // Binary STL and 3MF: the mesh never sits in memory whole. The merge streams the file
    // (uncommitted); then the check reads the pieces one at a time (check/partitioned_check.h),
    // each with the crease flips the merge made across its faces, and judges the zone where
    // they meet once. Where the parts cannot decide, the whole mesh is checked after all.
    // (The 3MF writer keeps every float exact, so the mesh checked is the file's.)
    auto t = Clock::now();
    std::unique_ptr<StlStreamWriter> stl;
    std::unique_ptr<ThreeMfStreamWriter> threeMf;
    if (format == MeshFormat::StlBinary) {
      stl = std::make_unique<StlStreamWriter>(path);
    } else {
      // a piece file holds at least a fifth of the XML its triangles and vertices make
      std::uint64_t pieceBytes = 0;
      for (const std::string& f : pieceFiles) {
        std::error_code ec;
        const auto size = std::filesystem::file_size(f, ec);
        if (!ec) pieceBytes += size;
      }
      threeMf = std::make_unique<ThreeMfStreamWriter>(path, request.threeMf, 5 * pieceBytes);
      threeMf->beginObject(request.objectName.empty() ? std::filesystem::path(path).stem().string()
                                                      : request.objectName);
    }
    struct Sink : PieceMerger::Sink {
      StlStreamWriter* stl;
      ThreeMfStreamWriter* threeMf;
      void vertex(const Vec3f& p) override {
        if (threeMf) threeMf->vertex(p);
      }
      void triangle(const Triangle& ids, const Vec3f& a, const Vec3f& b, const Vec3f& c) override {
        if (stl)
          stl->add(a, b, c);
        else
          threeMf->triangle(ids);
      }
    } sink;
    sink.stl = stl.get();
    sink.threeMf = threeMf.get();
    PieceMerger merger(sink);
    std::vector<std::size_t> fileOf(plan.jobs, 0);
    std::int64_t gridCells[3] = {0, 0, 0};
    for (std::size_t i = 0; i < pieceFiles.size(); ++i) {
      const MeshPiece piece = readRunPiece(plan, pieceFiles[i]);
      merger.add(piece);  // (refuses a job twice)
      fileOf[piece.job] = i;
      for (int a = 0; a < 3; ++a) gridCells[a] = piece.gridCells[a];
      report(ExportStage::Mesh, static_cast<double>(i + 1) / count);
    }
    merger.finish();
    std::unique_ptr<AtomicFile> pending;
    if (stl) {
      pending = stl->finish();
      result.triangles = stl->triangles();
    } else {
      threeMf->endObject();  // (the triangles spilled while vertices came follow them)
      pending = threeMf->finish();
      result.triangles = threeMf->triangles();
    }
    result.seconds[1] = since(t);

    if (request.check) {
      t = Clock::now();
      report(ExportStage::Check, 0.0);
      // each piece as its job judged it (without the triangles it left to the merge), and
      // those, as the merged mesh has them, with the zone
      auto part = [&](std::size_t job) {
        return pieceCheckedPart(readRunPiece(plan, pieceFiles[fileOf[job]]));
      };
      PartitionedCheck check(jobBoxes(plan, gridCells));
      // the pieces 90 % of the check's bar, the zone where they meet the rest
      const Progress pieces = Progress([&report](double f) {
                                report(ExportStage::Check, f);
                                return true;
                              }).sub(0.0, 0.9);
      bool inParts = true;
      for (std::uint32_t job = 0; job < plan.jobs && inParts; ++job) {
        inParts = summaryFiles.empty()
                      ? check.addPart(job, part(job))
                      : check.addSummary(job, readJudged(plan, job, summaryFiles[fileOf[job]]));
        pieces.count(job + 1, plan.jobs);
      }
      {
        TriangleMesh settled;
        for (const auto& [key, corners] : merger.settled()) {
          const auto base = static_cast<std::uint32_t>(settled.positions.size());
          settled.positions.insert(settled.positions.end(), corners.begin(), corners.end());
          settled.triangles.push_back({base, base + 1, base + 2});
        }
        check.addZoneFaces(settled);
      }
      std::optional<CheckReport> checked;
      if (inParts) checked = check.finish(merger.vertices(), part);
      result.checkedInParts = checked.has_value();
      if (!checked) checked = checkMesh(mergeInMemory(false));
      result.report = std::move(*checked);
      result.checked = true;
      result.seconds[2] = since(t);
      report(ExportStage::Check, 1.0);
      if (!result.report.printable() && !request.force) return result;
    }
    t = Clock::now();
    report(ExportStage::Write, 0.0);
    pending->commit();
    result.written = true;
    result.seconds[3] = since(t);
    report(ExportStage::Write, 1.0);
    return result;
  }

  auto t = Clock::now();
  TriangleMesh mesh = mergeInMemory(true);
  result.triangles = mesh.triangleCount();
  result.seconds[1] = since(t);

  if (request.check) {
    t = Clock::now();
    report(ExportStage::Check, 0.0);
    result.report = checkMesh(mesh, [&](double f) { report(ExportStage::Check, f); });
    result.checked = true;
    result.seconds[2] = since(t);
    if (!result.report.printable() && !request.force) return result;
  }
  t = Clock::now();
  report(ExportStage::Write, 0.0);
  writeMesh(mesh, path, format,
            [&](double f) { return !request.progress || request.progress(ExportStage::Write, f); });
  result.written = true;
  result.seconds[3] = since(t);
  report(ExportStage::Write, 1.0);
  return result;
}

}  // namespace frep
