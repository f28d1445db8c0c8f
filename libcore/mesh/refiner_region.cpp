// The refiner's region: the cubes to refine found (round the hidden parts' edges, and at the
// surface a level deeper), grown until no triangle reaches into them, and closed.
#include "mesh/refiner.h"

namespace frep {
namespace refinement {

void Refiner::grow(const std::vector<std::uint64_t>& seedCubes, std::size_t maxCubes) {
  std::vector<std::uint64_t> candidates = seedCubes;
  std::unordered_set<std::uint64_t> tried;
  while (!candidates.empty() && region_.size() < maxCubes) {
    checkCancel();
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    std::vector<std::uint64_t> fresh;
    for (std::uint64_t c : candidates)
      if (tried.insert(c).second && !isBanned(c)) fresh.push_back(c);
    evaluateCubes(fresh);
    std::vector<std::uint64_t> next, quiet;
    for (std::uint64_t id : fresh) {
      if (region_.size() >= maxCubes) break;
      std::int64_t c[3];
      cubeOf(id, c);
      if (hidesSomething(c, &next) || mustRefine_.count(id))
        region_.insert(id);
      else if (lookDeeper_)
        quiet.push_back(id);
    }
    for (std::uint64_t id : deeperShowsHidden(quiet)) {
      if (region_.size() >= maxCubes) break;
      region_.insert(id);
      std::int64_t c[3];
      cubeOf(id, c);
      for (int d = 0; d < 27; ++d) {
        const std::int64_t q[3] = {c[0] + d % 3 - 1, c[1] + (d / 3) % 3 - 1, c[2] + d / 9 - 1};
        if (d != 13 && validCube(q)) next.push_back(cubeId(q[0], q[1], q[2]));
      }
    }
    candidates.swap(next);
  }
  std::vector<std::uint64_t> forced;
  for (std::uint64_t id : forced_)
    if (!isBanned(id) && !region_.count(id)) forced.push_back(id);
  std::sort(forced.begin(), forced.end());
  evaluateCubes(forced);
  region_.insert(forced.begin(), forced.end());
}

void Refiner::surfaceCubesToLookAt(std::vector<std::uint64_t>* candidates,
                                   std::vector<std::uint64_t>* far,
                                   const std::vector<std::uint64_t>* only) {
  const auto& P = mesh_.positions;
  // Given `only`, the triangles are needed in those cubes and round them alone (a few
  // thousand cubes against a mesh of millions of triangles: no sort of them all).
  std::vector<std::uint64_t> wanted;
  if (only) {
    for (std::uint64_t id : *only) {
      std::int64_t c[3];
      cubeOf(id, c);
      for (int n = 0; n < 27; ++n) {
        const std::int64_t o[3] = {c[0] + n % 3 - 1, c[1] + (n / 3) % 3 - 1, c[2] + n / 9 - 1};
        if (validCube(o)) wanted.push_back(cubeId(o[0], o[1], o[2]));
      }
    }
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  }
  // the triangles by the cubes their boxes reach into (in parallel: millions of them)
  using CubeTriangle = std::pair<std::uint64_t, std::uint32_t>;
  tbb::enumerable_thread_specific<std::vector<CubeTriangle>> pairs;
  const std::size_t T = mesh_.triangles.size();
  tbb::parallel_for(std::size_t(0), (T + 4095) / 4096, [&](std::size_t block) {
    std::vector<CubeTriangle>& out = pairs.local();
    for (std::size_t t = 4096 * block; t < std::min(T, 4096 * (block + 1)); ++t) {
      const Triangle& tr = mesh_.triangles[t];
      std::int64_t lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = cubeIndexOf(a, std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]}));
        hi[a] = cubeIndexOf(a, std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]}));
      }
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
          for (std::int64_t i = lo[0]; i <= hi[0]; ++i) {
            const std::uint64_t id = cubeId(i, j, k);
            if (!only || std::binary_search(wanted.begin(), wanted.end(), id))
              out.push_back({id, static_cast<std::uint32_t>(t)});
          }
    }
  });
  std::vector<CubeTriangle> byCube;
  std::size_t count = 0;
  for (const auto& v : pairs) count += v.size();
  byCube.reserve(count);
  for (const auto& v : pairs) byCube.insert(byCube.end(), v.begin(), v.end());
  tbb::parallel_sort(byCube.begin(), byCube.end());
  std::vector<std::uint64_t> cubes;
  if (only) {
    cubes = *only;
  } else {
    for (const auto& [id, t] : byCube)
      if (cubes.empty() || cubes.back() != id) cubes.push_back(id);
  }
  auto trianglesOf = [&](std::uint64_t id) {
    return std::equal_range(byCube.begin(), byCube.end(), std::make_pair(id, std::uint32_t(0)),
                            [](const auto& u, const auto& w) { return u.first < w.first; });
  };
  // (in the mesher's cells at every level: the goal is theirs)
  const double farLimit = kFarCells * std::max({g_.base->h[0], g_.base->h[1], g_.base->h[2]});
  constexpr std::size_t kChunk = 256;
  struct Found {
    std::vector<std::uint64_t> candidates, far;
    std::vector<std::pair<std::uint64_t, std::uint8_t>> masks;
  };
  tbb::enumerable_thread_specific<Found> found;
  const std::size_t chunks = (cubes.size() + kChunk - 1) / kChunk;
  std::mutex progressMutex;  // (the caller's progress: one call at a time)
  std::size_t chunksDone = 0;
  std::atomic<bool> cancelled{false};
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t ch) {
    if (cancelled.load(std::memory_order_relaxed)) return;
    if (range_) {
      std::lock_guard<std::mutex> lock(progressMutex);
      if (!range_.count(chunksDone++, chunks)) cancelled = true;
    }
    const std::size_t from = ch * kChunk, to = std::min(cubes.size(), from + kChunk);
    QuarterSamples q;
    sampleQuarterPoints(cubes.data() + from, to - from, &q);
    const std::vector<double>&x = q.x, &y = q.y, &z = q.z, &v = q.v;
    Found& out = found.local();
    for (std::size_t i = from; i < to; ++i) {
      const std::size_t base = 125 * (i - from);
      auto in = [&](int qx, int qy, int qz) { return isInside(v[base + qx + 5 * qy + 25 * qz]); };
      bool shows = showsHidden([&](int dx, int dy, int dz) { return in(2 * dx, 2 * dy, 2 * dz); },
                               [](int, int, int) {}, [](int, int) {});
      const std::uint8_t mask = halfCubesShowingHidden(in);
      out.masks.push_back({cubes[i], mask});
      if (shows || mask) out.candidates.push_back(cubes[i]);
      if (farFromMesh(cubes[i], v.data() + base, x.data() + base, y.data() + base, z.data() + base,
                      farLimit, trianglesOf))
        out.far.push_back(cubes[i]);
    }
  });
  if (cancelled) throw Cancelled();
  stats_.evaluations += 125 * cubes.size();
  for (const Found& f : found) {
    for (const auto& [id, mask] : f.masks) deeperHides_[id] = mask;
    candidates->insert(candidates->end(), f.candidates.begin(), f.candidates.end());
    far->insert(far->end(), f.far.begin(), f.far.end());
  }
  std::sort(candidates->begin(), candidates->end());
  std::sort(far->begin(), far->end());
}

std::vector<std::uint64_t> Refiner::deeperShowsHidden(const std::vector<std::uint64_t>& cubes) {
  std::vector<std::uint64_t> out, todo;
  for (std::uint64_t id : cubes) {
    const auto it = deeperHides_.find(id);
    if (it == deeperHides_.end())
      todo.push_back(id);
    else if (it->second)
      out.push_back(id);
  }
  if (todo.empty()) return out;
  QuarterSamples q;
  sampleQuarterPoints(todo.data(), todo.size(), &q);
  stats_.evaluations += q.v.size();
  for (std::size_t i = 0; i < todo.size(); ++i) {
    const std::uint8_t mask = halfCubesShowingHidden(
        [&](int qx, int qy, int qz) { return isInside(q.v[125 * i + qx + 5 * qy + 25 * qz]); });
    deeperHides_[todo[i]] = mask;
    if (mask) out.push_back(todo[i]);
  }
  return out;
}

bool Refiner::hidesSomething(const std::int64_t c[3], std::vector<std::uint64_t>* next) const {
  auto queue = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    const std::int64_t q[3] = {x, y, z};
    if (validCube(q)) next->push_back(cubeId(x, y, z));
  };
  return showsHidden(
      [&](int dx, int dy, int dz) {
        const std::int64_t f[3] = {2 * c[0] + dx, 2 * c[1] + dy, 2 * c[2] + dz};
        return isInside(value(f));
      },
      [&](int a, int db, int dc) {  // the four cubes round that edge
        const int b = (a + 1) % 3, cc = (a + 2) % 3;
        for (int d = 0; d < 4; ++d) {
          std::int64_t q[3] = {c[0], c[1], c[2]};
          q[b] += db / 2 - (d & 1);
          q[cc] += dc / 2 - (d >> 1);
          queue(q[0], q[1], q[2]);
        }
      },
      [&](int a, int side) {  // the cube across that face
        std::int64_t q[3] = {c[0], c[1], c[2]};
        q[a] += side == 0 ? -1 : 1;
        queue(q[0], q[1], q[2]);
      });
}

void Refiner::span(int a, float mn, float mx, std::int64_t* lo, std::int64_t* hi) const {
  std::int64_t j = static_cast<std::int64_t>(std::floor((mn - g_.coord(a, 0)) / g_.h[a]));
  j = std::clamp<std::int64_t>(j, 0, points_[a] - 2);
  while (j > 0 && planeF(a, j) > mn) --j;
  while (j < points_[a] - 2 && planeF(a, j + 1) <= mn) ++j;
  if (mn == mx && mn == planeF(a, j)) {
    *lo = std::max<std::int64_t>(j - 1, 0);
    *hi = j;
    return;
  }
  *lo = j;
  std::int64_t k = j;
  while (k + 1 <= points_[a] - 2 && planeF(a, k + 1) < mx) ++k;
  *hi = k;
}

void Refiner::buildZone() {
  for (int a = 0; a < 3; ++a) nb_[a] = points_[a] / kBlock + 1;
  const std::size_t blocks = static_cast<std::size_t>(nb_[0] * nb_[1] * nb_[2]);
  zone_.assign(blocks, 0);
  zoneGrown_.assign(blocks, 0);
  auto mark = [&](std::vector<std::uint8_t>& bits, const std::int64_t c[3], std::int64_t reach) {
    std::int64_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<std::int64_t>(c[a] - reach, 0) / kBlock;
      hi[a] = std::min<std::int64_t>((c[a] + reach) / kBlock, nb_[a] - 1);
    }
    for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
          bits[static_cast<std::size_t>(i + nb_[0] * (j + nb_[1] * k))] = 1;
  };
  for (std::uint64_t id : region_) {
    std::int64_t c[3];
    cubeOf(id, c);
    mark(zone_, c, kZoneReach);
    mark(zoneGrown_, c, kZoneReach + kBlock);
  }
  // the triangles reaching into it, with the cubes their boxes reach into
  const auto& P = mesh_.positions;
  nearby_.clear();
  for (std::size_t t = 0; t < mesh_.triangles.size(); ++t) {
    const Triangle& tr = mesh_.triangles[t];
    // a triangle under a block across whose first vertex's block is not in the grown
    // zone has neither corner of its box in the zone
    bool small = true;
    std::int64_t v0[3];
    for (int a = 0; a < 3; ++a) {
      const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      small = small && (double(mx) - mn) < (kBlock - 2) * g_.h[a];
      v0[a] = cubeIndexOf(a, P[tr[0]][a]);
    }
    if (small && !zoneGrown_[blockOf(v0[0], v0[1], v0[2])]) continue;
    Near n;
    n.t = static_cast<std::uint32_t>(t);
    for (int a = 0; a < 3; ++a) {
      const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
      span(a, mn, mx, &n.lo[a], &n.hi[a]);
    }
    if (zone_[blockOf(n.lo[0], n.lo[1], n.lo[2])] || zone_[blockOf(n.hi[0], n.hi[1], n.hi[2])])
      nearby_.push_back(n);
  }
  flipEdge_.clear();
  for (std::size_t ni = 0; ni < nearby_.size(); ++ni) {
    const Near& n = nearby_[ni];
    int axes = 0;
    for (int a = 0; a < 3; ++a) axes += n.hi[a] > n.lo[a];
    if (axes != 1) continue;
    const Triangle& tr = mesh_.triangles[n.t];
    for (int e = 0; e < 3; ++e)
      flipEdge_[dirKey(tr[e], tr[(e + 1) % 3])] = static_cast<std::uint32_t>(ni);
  }
  byCube_.clear();
  for (std::size_t ni = 0; ni < nearby_.size(); ++ni) {
    const Near& n = nearby_[ni];
    for (std::int64_t k = n.lo[2]; k <= n.hi[2]; ++k)
      for (std::int64_t j = n.lo[1]; j <= n.hi[1]; ++j)
        for (std::int64_t i = n.lo[0]; i <= n.hi[0]; ++i)
          byCube_[cubeId(i, j, k)].push_back(static_cast<std::uint32_t>(ni));
  }
}

bool Refiner::unflip(std::uint32_t ni) {
  Near& n = nearby_[ni];
  int axis = -1;
  for (int a = 0; a < 3; ++a) {
    if (n.hi[a] == n.lo[a]) continue;
    if (axis >= 0 || n.hi[a] != n.lo[a] + 1) return false;
    axis = a;
  }
  if (axis < 0) return false;
  const float plane = planeF(axis, n.hi[axis]);
  const auto& P = mesh_.positions;
  auto inner = [&](std::uint32_t v) {
    for (int a = 0; a < 3; ++a)
      if (planeAt(a, P[v][a]) >= 0) return false;
    return true;
  };
  Triangle t = mesh_.triangles[n.t];
  for (int r = 0; r < 3; ++r) {
    const std::uint32_t v1 = t[r], a = t[(r + 1) % 3], v2 = t[(r + 2) % 3];
    if (P[a][axis] != plane || !inner(v1) || !inner(v2)) continue;
    if ((P[v1][axis] < plane) == (P[v2][axis] < plane)) continue;
    const auto it = flipEdge_.find(dirKey(v1, v2));
    if (it == flipEdge_.end()) return false;
    Near& m = nearby_[it->second];
    if (removed_[m.t]) return false;
    const Triangle u = mesh_.triangles[m.t];
    int s = 0;
    while (s < 3 && !(u[s] == v1 && u[(s + 1) % 3] == v2)) ++s;
    if (s == 3) return false;
    const std::uint32_t b = u[(s + 2) % 3];
    if (P[b][axis] != plane) return false;
    mesh_.triangles[n.t] = {v1, a, b};
    mesh_.triangles[m.t] = {v2, b, a};
    setSpan(n);
    setSpan(m);
    flipEdge_.erase(dirKey(v1, v2));
    flipEdge_.erase(dirKey(v2, v1));
    ++stats_.unflipped;
    return true;
  }
  return false;
}

void Refiner::close(std::size_t maxCubes) {
  const std::size_t T = mesh_.triangles.size();
  removed_.assign(T, 0);
  buildZone();
  std::vector<std::uint64_t> queue(region_.begin(), region_.end());
  for (;;) {
    checkCancel();
    // triangles reaching into the cubes queued go; the cubes they reach into join
    std::vector<std::uint64_t> joined;
    for (std::uint64_t id : queue) {
      const auto it = byCube_.find(id);
      if (it == byCube_.end()) continue;
      for (std::uint32_t ni : it->second) {
        if (removed_[nearby_[ni].t]) continue;
        if (unflip(ni) && !inSpan(nearby_[ni], id)) continue;  // now in the other cube alone
        const Near& n = nearby_[ni];
        removed_[n.t] = 1;
        std::vector<std::uint64_t> range;
        for (std::int64_t k = n.lo[2]; k <= n.hi[2]; ++k)
          for (std::int64_t j = n.lo[1]; j <= n.hi[1]; ++j)
            for (std::int64_t i = n.lo[0]; i <= n.hi[0]; ++i) range.push_back(cubeId(i, j, k));
        join(range, &joined);
      }
    }
    throwFailures();
    if (joined.empty()) {
      // A refined cube's crossed grid edge with no vertex: flat-vertex removal took it and
      // fanned its four cubes together, so they are refined together.
      findEdgeVertices();
      for (std::uint64_t id : region_) {
        std::int64_t c[3];
        cubeOf(id, c);
        for (int a = 0; a < 3; ++a) {
          const int b = (a + 1) % 3, cc = (a + 2) % 3;
          for (int e = 0; e < 4; ++e) {
            std::int64_t l[3] = {c[0], c[1], c[2]};
            l[b] += e & 1;
            l[cc] += e >> 1;
            const std::int64_t f0[3] = {2 * l[0], 2 * l[1], 2 * l[2]};
            std::int64_t f2[3] = {f0[0], f0[1], f0[2]};
            f2[a] += 2;
            if (isInside(value(f0)) == isInside(value(f2))) continue;
            if (edgeVertex_.count(g_.linear(l[0], l[1], l[2]) * 3 + static_cast<std::uint64_t>(a)))
              continue;
            std::vector<std::uint64_t> round;
            for (int d = 0; d < 4; ++d) {
              std::int64_t q[3] = {l[0], l[1], l[2]};
              q[b] -= d & 1;
              q[cc] -= d >> 1;
              if (validCube(q)) round.push_back(cubeId(q[0], q[1], q[2]));
            }
            join(round, &joined);
          }
        }
      }
      throwFailures();
      if (joined.empty()) break;
    }
    std::sort(joined.begin(), joined.end());
    joined.erase(std::unique(joined.begin(), joined.end()), joined.end());
    if (region_.size() + joined.size() > 2 * maxCubes)
      throw Abort("the region grew past its limit");
    evaluateCubes(joined);
    region_.insert(joined.begin(), joined.end());
    queue = joined;
    // a cube joined near the zone's rim: the zone grows (triangles beyond it may reach in)
    bool rim = false;
    for (std::uint64_t id : joined) {
      std::int64_t c[3];
      cubeOf(id, c);
      if (!inZone(c, 2)) rim = true;
    }
    if (rim) {
      buildZone();
      queue.assign(region_.begin(), region_.end());
    }
  }
  cubes_.assign(region_.begin(), region_.end());
  std::sort(cubes_.begin(), cubes_.end());
}

void Refiner::setSpan(Near& n) const {
  const auto& P = mesh_.positions;
  const Triangle& tr = mesh_.triangles[n.t];
  for (int a = 0; a < 3; ++a) {
    const float mn = std::min({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
    const float mx = std::max({P[tr[0]][a], P[tr[1]][a], P[tr[2]][a]});
    span(a, mn, mx, &n.lo[a], &n.hi[a]);
  }
}

void Refiner::join(const std::vector<std::uint64_t>& cubes, std::vector<std::uint64_t>* joined) {
  bool conflict = false;
  for (std::uint64_t id : cubes) conflict = conflict || isBanned(id);
  if (!conflict) {
    for (std::uint64_t id : cubes)
      if (!region_.count(id)) joined->push_back(id);
    return;
  }
  for (std::uint64_t id : cubes)
    if (region_.count(id)) failed_.cubes.push_back(id);
}

}  // namespace refinement
}  // namespace frep
