// Enveloping (seed 003, 3.5): CVs of chosen levels bound to the frames of skeleton segments,
// so that moving a segment carries them along. A CV near a joint takes a frame between the two
// segments' (their rotations interpolated about the joint, not their positions averaged: an
// average pulls the inner side of a bent joint towards its axis). CVs of finer levels that are
// not enveloped keep their offsets and so follow their parents' frames. Enveloping level 0 as
// well as a level refined around each joint is seed 003's figure 3.2: the joint bends without
// collapsing.
#pragma once

#include <cstddef>
#include <vector>

#include "hspline/hspline.h"

namespace frep {

// A skeleton segment: where it lies in the rest pose, and the rigid motion (rotation and
// translation, q = R p + t) from its rest pose to where it is now.
struct HsSegment {
  Vec3 start{0, 0, 0}, end{0, 0, 0};
  Mat34 motion{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
};

struct HsEnvelopeSettings {
  // The enveloped levels. Level 0's CVs go each with its nearest segment; a finer level's CVs
  // within `jointReach` of a joint blend the two segments' frames across it.
  std::vector<int> levels{0, 1};
  // Half the width of the band around a joint where finer CVs blend (and where level 0 is
  // refined); 0: 1.25 times the mean edge of level 0's control net.
  double jointReach = 0;
  // Refine level 0 around each joint first (in the result only), so that level 1 has CVs there.
  bool refineJoints = true;
};

struct HsEnvelope {
  HSpline surface;                           // the rest hierarchy deformed
  std::vector<std::size_t> boundPerSegment;  // CVs whose largest weight is that segment's
  std::size_t blended = 0;                   // CVs bound to two segments
  std::vector<std::size_t> boundPerLevel;    // per entry of settings.levels
  std::vector<Vec3> joints;                  // in the rest pose
  double jointReach = 0;                     // as used
};

// Two segments meet at a joint when one's end lies on the next one's start (within 1e-6 of
// the segments' size); the segments are taken as a chain in the order given. An enveloped
// level the hierarchy does not have binds nothing (boundPerLevel says 0). Throws ModelError
// naming the segment for one of zero length or a motion that is not rigid, and for a negative
// level or reach.
HsEnvelope envelope(const HSpline& rest, const std::vector<HsSegment>& segments,
                    const HsEnvelopeSettings& settings);

}  // namespace frep
