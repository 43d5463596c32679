// The one exception type of mbrt.
#pragma once

#include <stdexcept>

namespace mbrt {

// Every error mbrt reports: bad scenes, bad options, bad files, exceeded
// memory budgets. The message says what and where.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mbrt
