// Kind<N> for the context's branching factor (BuildOptions::branching: 2, 4
// or 8): every N-wide structure is made through this one switch.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

template <template <int> class Kind>
std::unique_ptr<Structure> makeForBranching(const SceneContext& context) {
  switch (context.options().branching) {
    case 2: return std::make_unique<Kind<2>>(context);
    case 4: return std::make_unique<Kind<4>>(context);
    default: return std::make_unique<Kind<8>>(context);
  }
}

// The same for kinds made with a second parameter (a leaf format).
template <template <int, class> class Kind, class Arg>
std::unique_ptr<Structure> makeForBranching(const SceneContext& context) {
  switch (context.options().branching) {
    case 2: return std::make_unique<Kind<2, Arg>>(context);
    case 4: return std::make_unique<Kind<4, Arg>>(context);
    default: return std::make_unique<Kind<8, Arg>>(context);
  }
}

}  // namespace mbrt::detail
