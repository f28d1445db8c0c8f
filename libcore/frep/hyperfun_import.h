// HyperFun programs (.hf) as FRep models. The program runs once with the point unknown:
// conditions and loops over numbers run as HyperFun runs them, and what depends on the point
// becomes a tree: each library primitive a formula node holding HyperFun's own expression
// (hfSphere is R^2 - |x - c|^2, not a distance), | & \ ~ union, intersection, difference and
// complement nodes with alpha = 0 (HyperFun's R-functions), hfBlendUni/hfBlendInt blend nodes
// with alpha = 0, the rest formula nodes over those. Values at every point are HyperFun's.
// docs/hyperfun.md lists what is translated and what is not.
#pragma once

#include <string>

#include "frep/model_json.h"

namespace frep {

// The model of the program's body named my_model, or of its last body when none is. `source`
// names the program in errors ("part.hf:12:7: ..."). Throws ModelError.
Model importHyperFun(const std::string& text, const std::string& source);

// True for a path whose extension is .hf (any case).
bool isHyperFunPath(const std::string& path);

}  // namespace frep
