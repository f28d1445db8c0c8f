#include "io/mesh_piece_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "base/atomic_file.h"
#include "base/errors.h"

namespace frep {

namespace {

constexpr char kMagic[8] = {'F', 'R', 'E', 'P', 'P', 'C', 'E', '1'};

// The header after the magic: run, job, jobs, grid and the job's cells, then the counts.
struct Header {
  std::uint64_t runId;
  std::uint32_t job, jobs;
  std::int64_t gridCells[3], cellLo[3], cellHi[3];
  std::uint64_t vertices, triangles, pending;
};
static_assert(sizeof(Header) == 8 + 8 + 72 + 24, "the header has no padding");

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};

}  // namespace

void writePieceFile(const MeshPiece& p, const std::string& path) {
  AtomicFile f(path);
  Header h{};
  h.runId = p.runId;
  h.job = p.job;
  h.jobs = p.jobs;
  for (int a = 0; a < 3; ++a) {
    h.gridCells[a] = p.gridCells[a];
    h.cellLo[a] = p.cellLo[a];
    h.cellHi[a] = p.cellHi[a];
  }
  h.vertices = p.keys.size();
  h.triangles = p.triangles.size();
  h.pending = p.pendingFlips.size();
  f.write(kMagic, sizeof(kMagic));
  f.write(&h, sizeof(h));
  f.write(p.keys.data(), p.keys.size() * sizeof(std::uint64_t));
  f.write(p.positions.data(), p.positions.size() * sizeof(Vec3f));
  f.write(p.triangles.data(), p.triangles.size() * sizeof(Triangle));
  f.write(p.pendingFlips.data(), p.pendingFlips.size() * sizeof(std::uint32_t));
  f.commit();
}

MeshPiece readPieceFile(const std::string& path) {
  auto refuse = [&](const std::string& why) -> FileError {
    return FileError(path + ": not a brick piece: " + why);
  };
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw FileError(path + ": cannot open: " + std::strerror(errno));
  std::FILE* f = file.get();
  if (std::fseek(f, 0, SEEK_END) != 0) throw refuse("cannot seek");
  const long size = std::ftell(f);
  std::rewind(f);
  char magic[8];
  Header h{};
  if (size < static_cast<long>(sizeof(magic) + sizeof(h)) || std::fread(magic, 1, 8, f) != 8 ||
      std::memcmp(magic, kMagic, 8) != 0 || std::fread(&h, sizeof(h), 1, f) != 1)
    throw refuse("no FREPPCE1 header");
  // the counts must account for the file's size exactly before anything is allocated
  const unsigned long long body = static_cast<unsigned long long>(size) - sizeof(magic) - sizeof(h);
  const unsigned long long limit = 1ull << 40;
  if (h.vertices > limit || h.triangles > limit || h.pending > limit ||
      h.vertices * (8 + 12) + h.triangles * 12 + h.pending * 4 != body)
    throw refuse("its counts do not match its size");
  if (h.jobs == 0 || h.job >= h.jobs)
    throw refuse("job " + std::to_string(h.job) + " of " + std::to_string(h.jobs));
  MeshPiece p;
  p.runId = h.runId;
  p.job = h.job;
  p.jobs = h.jobs;
  for (int a = 0; a < 3; ++a) {
    if (h.gridCells[a] < 1 || h.cellLo[a] < 0 || h.cellLo[a] >= h.cellHi[a] ||
        h.cellHi[a] > h.gridCells[a])
      throw refuse("its job's cells lie outside its grid");
    p.gridCells[a] = h.gridCells[a];
    p.cellLo[a] = h.cellLo[a];
    p.cellHi[a] = h.cellHi[a];
  }
  p.keys.resize(h.vertices);
  p.positions.resize(h.vertices);
  p.triangles.resize(h.triangles);
  p.pendingFlips.resize(h.pending);
  auto read = [&](void* data, std::size_t bytes) {
    if (bytes && std::fread(data, 1, bytes, f) != bytes) throw refuse("truncated");
  };
  read(p.keys.data(), p.keys.size() * sizeof(std::uint64_t));
  read(p.positions.data(), p.positions.size() * sizeof(Vec3f));
  read(p.triangles.data(), p.triangles.size() * sizeof(Triangle));
  read(p.pendingFlips.data(), p.pendingFlips.size() * sizeof(std::uint32_t));
  for (std::size_t v = 1; v < p.keys.size(); ++v)
    if (p.keys[v] <= p.keys[v - 1]) throw refuse("its vertex keys are not sorted and unique");
  for (const Triangle& t : p.triangles)
    for (std::uint32_t v : t)
      if (v >= h.vertices) throw refuse("a triangle names a vertex it does not have");
  for (std::uint32_t t : p.pendingFlips)
    if (t >= h.triangles) throw refuse("a pending flip names a triangle it does not have");
  return p;
}

}  // namespace frep
