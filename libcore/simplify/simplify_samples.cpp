// The surface samples a change must keep covered: each sample of the mesher's surface stays
// near a face after a collapse or a flip (simplify/region_simplifier.h).
#include "simplify/region_simplifier.h"

namespace frep {
namespace simplifying {

bool RegionSimplifier::samplesCovered(std::uint32_t gv, std::uint32_t gu) {
  const std::uint32_t lv = local(gv);
  star_.clear();
  for (std::uint32_t f : around_[lv])
    if (deadFace_[f] == kLive) star_.push_back(f);
  if (gu != kNone)
    for (std::uint32_t f : around_[local(gu)])
      if (deadFace_[f] == kLive) star_.push_back(f);
  auto covered = [&](const Vec3f& q) {
    for (std::uint32_t f : star_)
      if (sampleNear(q, f)) return true;
    return false;
  };
  for (const Vec3f& q : s_.samples[gv])
    if (!covered(q)) return false;
  if (gu != kNone)
    for (const Vec3f& q : s_.samples[gu])
      if (!covered(q)) return false;
  return true;
}

bool RegionSimplifier::quadSamplesCovered() {
  star_.clear();
  for (std::uint32_t w : flipCorners_)
    for (std::uint32_t f : around_[local(w)])
      if (deadFace_[f] == kLive) star_.push_back(f);
  std::sort(star_.begin(), star_.end());
  star_.erase(std::unique(star_.begin(), star_.end()), star_.end());
  sampleMoves_.clear();
  for (int c = 0; c < 4; ++c) {
    const std::uint32_t w = flipCorners_[c];
    const std::vector<Vec3f>& samples = s_.samples[w];
    for (std::uint32_t i = 0; i < samples.size(); ++i) {
      bool own = false;
      for (std::uint32_t f : around_[local(w)])
        if (deadFace_[f] == kLive && sampleNear(samples[i], f)) {
          own = true;
          break;
        }
      if (own) continue;
      int to = -1;
      for (std::uint32_t f : star_) {
        if (!sampleNear(samples[i], f)) continue;
        for (int k = 0; k < 4 && to < 0; ++k)
          if (holds(faces_[f], flipCorners_[k])) to = k;
        break;
      }
      if (to < 0) return false;
      sampleMoves_.push_back({c, i, to});
    }
  }
  return true;
}

}  // namespace simplifying
}  // namespace frep
