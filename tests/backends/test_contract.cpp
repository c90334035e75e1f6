// The backend contract (backend_contract.hpp) for every backend the project has; one this binary
// was built without is skipped, saying so.
#include "backend_contract.hpp"

namespace chainmail::test {

INSTANTIATE_TEST_SUITE_P(Every, BackendContract, ::testing::ValuesIn(known_backend_names()),
                         backend_param_name);

}  // namespace chainmail::test
