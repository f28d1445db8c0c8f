// HyperFun's F-rep library (hfSphere, hfBlock, hfBlendUni, hfRotate3DZ, ...), each with the
// value its library computes, written out independently from its published definitions.
// Primitives and blends return a value; transformations change the coordinate array they are
// given (as in HyperFun: `dummy = hfShift3D(xt, 1, 0, 0);` moves what later uses xt) and
// return 1.
#pragma once

#include <string>
#include <vector>

#include "frep/hyperfun_expr.h"

namespace frep::hyperfun {

// One argument of a library call: a number, or an array (which the call may change).
struct LibraryArgument {
  ExprPtr value;
  std::vector<ExprPtr>* array = nullptr;  // items may be null: not given a value yet
  std::string name;                       // the array's name, for messages
};

// The argument kinds of a library function, 'A' (array) or 'R' (number), in order; empty for
// a name that is not one FRepCAD computes. `unsupported` says why for HyperFun functions it
// does not (convolution lines, noise, attributes, ...), empty otherwise.
std::string libraryArguments(const std::string& name, std::string* unsupported = nullptr);

ExprPtr callLibrary(const std::string& name, std::vector<LibraryArgument>& args, ExprBuilder& b);

// The names FRepCAD computes, for docs and messages.
std::vector<std::string> libraryNames();

}  // namespace frep::hyperfun
