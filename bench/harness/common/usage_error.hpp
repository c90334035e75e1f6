// A command line that cannot be run: a bad flag value, an unknown or unbuilt backend name.
// Apart from SceneError (a bad scene file or --set); the command line reports both on one line
// and exits 2.
#pragma once

#include <stdexcept>
#include <string>

namespace chainmail {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace chainmail
