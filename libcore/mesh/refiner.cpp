// The refiner's public steps (mesh/refiner.h): the cubes round hidden parts, what a deeper
// level takes from the one above, evaluation, and run(), which goes region, seam, half cubes
// and assembly, starting again without the cubes a case fails in.
#include "mesh/refiner.h"

namespace frep {
namespace refinement {

void Refiner::sampleQuarterPoints(const std::uint64_t* cubes, std::size_t count,
                                  QuarterSamples* out) const {
  const RefinementGrid quarter = g_.finer().finer();
  const std::size_t n = 125 * count;
  out->x.resize(n);
  out->y.resize(n);
  out->z.resize(n);
  out->v.resize(n);
  for (std::size_t i = 0; i < count; ++i) {
    std::int64_t c[3];
    cubeOf(cubes[i], c);
    for (int d = 0; d < 125; ++d) {
      out->x[125 * i + d] = quarter.coord(0, 4 * c[0] + d % 5);
      out->y[125 * i + d] = quarter.coord(1, 4 * c[1] + (d / 5) % 5);
      out->z[125 * i + d] = quarter.coord(2, 4 * c[2] + d / 25);
    }
  }
  field_.evalBatch(out->x.data(), out->y.data(), out->z.data(), n, out->v.data());
  for (std::size_t k = 0; k < n; ++k)
    out->v[k] = combine(out->v[k], g_.boxField(out->x[k], out->y[k], out->z[k]));
}

std::vector<std::uint64_t> Refiner::cubesRound(const std::vector<std::uint64_t>& edges) const {
  std::vector<std::uint64_t> cubes;
  for (std::uint64_t e : edges) {
    const int a = static_cast<int>(e % 3);
    std::int64_t l[3];
    cubeOf(e / 3, l);
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int d = 0; d < 4; ++d) {
      std::int64_t q[3] = {l[0], l[1], l[2]};
      q[b] -= d & 1;
      q[c] -= d >> 1;
      if (validCube(q)) cubes.push_back(cubeId(q[0], q[1], q[2]));
    }
  }
  return cubes;
}

std::vector<std::uint64_t> Refiner::finerCandidates() const {
  std::vector<std::uint64_t> out;
  out.reserve(8 * cubes_.size());
  for (std::uint64_t id : cubes_) {
    std::int64_t c[3];
    cubeOf(id, c);
    // the half cubes a look a level deeper showed something in (all where none was taken)
    const auto seen = deeperHides_.find(id);
    const unsigned mask = seen == deeperHides_.end() ? 0xffu : seen->second;
    for (int h = 0; h < 8; ++h)
      if (mask & (1u << h)) out.push_back(halfCubeId(c, h));
  }
  std::sort(out.begin(), out.end());
  return out;
}

void Refiner::recordSides() {
  sides_.clear();
  for (std::uint64_t id : cubes_) {
    std::int64_t c[3];
    cubeOf(id, c);
    for (int d = 0; d < 27; ++d) {
      const std::int64_t f[3] = {2 * c[0] + d % 3, 2 * c[1] + (d / 3) % 3, 2 * c[2] + d / 9};
      const std::uint64_t key = fineKey(f);
      if (sides_.count(key)) continue;
      double v = value(f);
      const bool side = fineSign(f);
      if (isInside(v) != side)
        v = side ? std::numeric_limits<double>::min() : -std::numeric_limits<double>::min();
      sides_[key] = v;
    }
  }
}

void Refiner::run(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes) {
  const TriangleMesh original = mesh_;
  for (int attempt = 0;; ++attempt) {
    try {
      grow(seedCubes, maxCubes);  // (a restart reports where it got: the bar never moves back)
      if (region_.empty()) return;
      at_ = std::max(at_, 0.2);
      close(maxCubes);
      at_ = std::max(at_, 0.5);
      checkCancel();
      findSeam();
      for (auto& [key, face] : seam_) {
        try {
          cutSeamFace(face);
        } catch (const Abort&) {
          std::int64_t below[3] = {face.cell[0], face.cell[1], face.cell[2]};
          below[face.axis] -= 1;
          const std::uint64_t up = cubeId(face.cell[0], face.cell[1], face.cell[2]),
                              down = cubeId(below[0], below[1], below[2]);
          failed_.extra.push_back(inOmega(below) ? up : down);
          failed_.fallback.push_back(inOmega(below) ? down : up);
        }
      }
      throwFailures();
      checkCancel();
      meshHalfCubes();
      splitTriangles();
      if (keepSides_) recordSides();
      assemble();
      return;
    } catch (const CubeFailure& f) {
      if (attempt == kMaxRestarts) throw Abort("too many cubes left out");
      banned_.insert(f.cubes.begin(), f.cubes.end());
      bool blocked = false;
      for (std::uint64_t id : f.extra) {
        if (!isBanned(id))
          forced_.insert(id);
        else
          blocked = true;
      }
      if (blocked) banned_.insert(f.fallback.begin(), f.fallback.end());
      stats_.cubesLeftOut = banned_.size();
      reset(original);
    }
  }
}

void Refiner::evaluate(const std::vector<std::array<std::int64_t, 3>>& points) {
  std::vector<double> x, y, z, v;
  std::vector<std::uint64_t> keys;
  for (const auto& p : points) {
    const std::uint64_t k = fineKey(p.data());
    if (values_.count(k)) continue;
    values_[k] = 0.0;  // (reserved: filled below)
    keys.push_back(k);
    x.push_back(fineCoord(0, p[0]));
    y.push_back(fineCoord(1, p[1]));
    z.push_back(fineCoord(2, p[2]));
  }
  if (keys.empty()) return;
  v.resize(keys.size());
  field_.evalBatch(x.data(), y.data(), z.data(), keys.size(), v.data());
  stats_.evaluations += keys.size();
  for (std::size_t i = 0; i < keys.size(); ++i)
    values_[keys[i]] = combine(v[i], g_.boxField(x[i], y[i], z[i]));
}

std::vector<std::uint64_t> Refiner::halvesOfFarCubes() const {
  std::vector<std::uint64_t> out;
  for (std::uint64_t id : mustRefine_) {
    if (!region_.count(id)) continue;
    std::int64_t c[3];
    cubeOf(id, c);
    for (int h = 0; h < 8; ++h) out.push_back(halfCubeId(c, h));
  }
  std::sort(out.begin(), out.end());
  return out;
}

void Refiner::handDown(Refiner& next) const {
  for (const auto& [key, v] : sides_) {
    std::int64_t f[3];
    f[0] = static_cast<std::int64_t>(key % finePoints_[0]);
    f[1] = static_cast<std::int64_t>((key / finePoints_[0]) % finePoints_[1]);
    f[2] = static_cast<std::int64_t>(key / (finePoints_[0] * finePoints_[1]));
    const std::int64_t there[3] = {2 * f[0], 2 * f[1], 2 * f[2]};
    next.values_[next.fineKey(there)] = v;
  }
  next.above_ = this;
}

void Refiner::reset(const TriangleMesh& original) {
  mesh_ = original;
  region_.clear();
  cubes_.clear();
  removed_.clear();
  seam_.clear();
  cells_.clear();
  edgeVertex_.clear();
  rootVertex_.clear();
  roots_.clear();
  stats_.cubes = stats_.trianglesRemoved = stats_.trianglesAdded = 0;
}

void Refiner::evaluateCubes(const std::vector<std::uint64_t>& cubes) {
  std::vector<std::array<std::int64_t, 3>> pts;
  for (std::uint64_t id : cubes) {
    std::int64_t c[3];
    cubeOf(id, c);
    for (int d = 0; d < 27; ++d)
      pts.push_back({2 * c[0] + d % 3, 2 * c[1] + (d / 3) % 3, 2 * c[2] + d / 9});
  }
  evaluate(pts);
}

}  // namespace refinement
}  // namespace frep
