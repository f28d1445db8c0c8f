// Brick jobs: an export cut into jobs that any process or machine can run, each
// meshing a box of the mesher's bricks into a piece file (io/mesh_piece_file.h), and a merge
// that welds the pieces by key, checks the mesh and writes it atomically. The mesh is the one
// exportField writes for the same box and options, up to the order of its vertices and
// triangles. The scheduling (Dask distributed) is frepcore.distributed's.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "base/mesh_piece.h"
#include "frep/field.h"
#include "mesh/mesher.h"
#include "pipeline/export_pipeline.h"

namespace frep {

// At most this many jobs in one run.
constexpr std::uint32_t kMaxBrickJobs = 1u << 16;

struct BrickJobPlan {
  MeshingBox box;
  MeshSettings mesh;  // mesher, sharpFeatures and dropFlatVertices apply; the rest stay default
  std::uint32_t jobs = 1;
  std::int64_t bricks[3] = {1, 1, 1};  // the mesher's bricks per axis
  std::int64_t split[3] = {1, 1, 1};   // jobs per axis (their product is `jobs`)
  std::uint64_t runId = 0;             // what every piece of the run carries
};

// A 64-bit fingerprint of a text (FNV-1a): the model's part of a run's id.
std::uint64_t textFingerprint(const std::string& text);

// The settings a brick job cannot take yet (a refinement, straightened creases, a
// tolerance): SettingError naming the first. planBrickJobs checks them too.
void checkBrickJobSettings(const MeshSettings& settings);

// Splits the box's bricks into `jobs` boxes of bricks, as even and as cubic as the job
// count's factors allow. `model` is a fingerprint of the model (textFingerprint of its JSON).
// Throws ModelError for a job count below 1, above kMaxBrickJobs or above what the bricks
// allow (naming the bricks per axis), SettingError for settings a job cannot take (a
// refinement, straightened creases, a tolerance).
BrickJobPlan planBrickJobs(const MeshingBox& box, const MeshSettings& settings, std::uint32_t jobs,
                           std::uint64_t model);

// The mesher's options every job of the run uses (no normals: pieces carry positions).
MeshingOptions brickMeshingOptions(const BrickJobPlan& plan);

// Job `job`'s bricks [lo, hi). Throws ModelError for a job out of range.
void jobBricks(const BrickJobPlan& plan, std::uint32_t job, std::int64_t lo[3], std::int64_t hi[3]);

// Meshes one job. progress(fraction) false cancels (Cancelled).
MeshPiece runBrickJob(const Field& field, const BrickJobPlan& plan, std::uint32_t job,
                      const std::function<bool(double)>& progress = nullptr);

// The part of a piece a check judges where the piece was made: its triangles but those it
// left to the merge (pendingFlips), which the merge's check takes with the zone instead.
TriangleMesh pieceCheckedPart(const MeshPiece& piece);
// That judgement (check/partitioned_check.h), made by the job itself: the summary the merge
// takes instead of reading the piece for its check.
std::vector<char> judgeBrickPiece(const BrickJobPlan& plan, const MeshPiece& piece);

// Reads the run's piece files one by one and welds them, checks the mesh (unless
// request.check is false) and writes `path` atomically as exportField does: nothing written
// when the check refuses (unless request.force) or on a cancel. request.box, tolerance, stats
// and normals do not apply (the plan fixed the box; pieces carry positions only). A binary
// STL is streamed and checked piece by piece; `summaryFiles` (one per piece, in the same
// order: judgeBrickPiece's bytes) save the merge that judgement. Throws FileError for a
// missing or foreign piece or summary, ModelError, Cancelled.
ExportResult exportPieces(const BrickJobPlan& plan, const std::vector<std::string>& pieceFiles,
                          const ExportRequest& request, const std::string& path,
                          const std::vector<std::string>& summaryFiles = {});

}  // namespace frep
