// Backend names as the command line and the notes print them: which are built into this binary,
// which the project has but this binary was configured without.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

// the backends built into this binary, in the registry's order
std::vector<std::string> built_backend_names();
// a backend the project has that this binary was built without (CHAINMAIL_WITH_BULLET=OFF, ...)
bool backend_known_unbuilt(const std::string& name);
// "a, b, c"
std::string join_names(const std::vector<std::string>& names);

}  // namespace chainmail
