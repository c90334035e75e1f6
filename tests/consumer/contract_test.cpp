// chainmail's backend contract on the outside backend, through the installed package.
#include <chainmail/testing/backend_contract.hpp>

#include <stdexcept>
#include <string>

#include "relaxed_backend.hpp"

namespace chainmail::test {

INSTANTIATE_TEST_SUITE_P(Outside, BackendContract, ::testing::Values(std::string("relaxed")),
                         backend_param_name);

TEST(OutsideRegistry, TheBackendIsKnownBuiltAndItsNameTaken) {
  ASSERT_TRUE(backend_built("relaxed"));
  EXPECT_EQ(known_backend_names().back(), "relaxed");
  EXPECT_EQ(find_backend("relaxed")->knobs.size(), 3u);
  try {
    consumer::register_relaxed_backend();
    FAIL() << "a second backend named relaxed was taken";
  } catch (const std::invalid_argument& error) {
    const std::string taken = "register_backend: backend 'relaxed': the name is taken";
    EXPECT_TRUE(std::string(error.what()).starts_with(taken)) << error.what();
  }
}

}  // namespace chainmail::test

int main(int argc, char** argv) {
  consumer::register_relaxed_backend();  // before any test reads the registry
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
