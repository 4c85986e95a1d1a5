#include "shared_gateway.hpp"

#include <exception>

namespace integration {

void SharedGatewayTest::start_shared(const GatewayOptions& options) {
  start_error_.clear();
  try {
    directory_ = std::make_unique<TestDirectory>();
    gateway_ = std::make_unique<Gateway>(directory_->path(), options);
    gateway_->start();
    gateway_->wait_online();
  } catch (const std::exception& error) {
    start_error_ = error.what();
    gateway_.reset();
  }
}

void SharedGatewayTest::stop_shared() {
  if (gateway_ && gateway_->daemon().running()) {
    const ExitStatus status = gateway_->daemon().terminate();
    if (!status.exited_with(0)) {
      ADD_FAILURE() << "wheeltecd ended with " << status.describe() << " on SIGTERM\n" << gateway_->logs();
    }
  }
  gateway_.reset();
  directory_.reset();
}

void SharedGatewayTest::SetUp() {
  if (!gateway_) GTEST_FAIL() << "the gateway did not start: " << start_error_;
  if (!gateway_->daemon().running()) GTEST_FAIL() << "wheeltecd has ended\n" << gateway_->logs();
  gateway_->connect().call("stop");
}

void SharedGatewayTest::TearDown() {
  if (HasFailure() && gateway_) std::cerr << gateway_->logs();
}

}  // namespace integration
