#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "gateway.hpp"
#include "test_environment.hpp"

namespace integration {

// Base of the test suites that share one emulator and daemon: started once by the
// suite's SetUpTestSuite (start_shared), stopped by its TearDownTestSuite.
class SharedGatewayTest : public ::testing::Test {
 protected:
  static void start_shared(const GatewayOptions& options);
  static void stop_shared();
  static Gateway& gateway() { return *gateway_; }
  static const std::filesystem::path& directory() { return directory_->path(); }

  // Fails the test when the suite's gateway did not start or has died; releases control.
  void SetUp() override;
  void TearDown() override;

 private:
  static inline std::unique_ptr<TestDirectory> directory_;
  static inline std::unique_ptr<Gateway> gateway_;
  static inline std::string start_error_;
};

}  // namespace integration
