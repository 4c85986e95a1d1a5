#include "wheeltec/client/client.hpp"

#include <boost/system/system_error.hpp>

namespace wheeltec::client {
namespace {

// Runs `io` until `done`; the connection's reply timeout bounds the wait.
void run_until(boost::asio::io_context& io, const bool& done) {
  io.restart();
  while (!done && io.run_one() > 0) {
  }
}

std::string error_message(const Json& error) {
  const auto message = error.is_object() ? error.find("message") : error.end();
  return message != error.end() && message->is_string() ? message->get<std::string>() : "malformed error answer";
}

}  // namespace

RpcError::RpcError(const std::string& method, const Json& error)
    : std::runtime_error(method + ": " + error_message(error) + " (code " +
                         std::to_string(error.is_object() ? error.value("code", 0) : 0) + ")"),
      code_(error.is_object() ? error.value("code", 0) : 0),
      message_(error_message(error)),
      data_(error.is_object() ? error.value("data", Json()) : Json()) {}

Client::Client(const std::string& socket_path) : connection_(io_.get_executor()) {
  bool done = false;
  boost::system::error_code result;
  connection_.async_connect(socket_path, [&](boost::system::error_code ec) {
    result = ec;
    done = true;
  });
  run_until(io_, done);
  if (result) throw boost::system::system_error(result, "cannot reach wheeltecd at " + socket_path);
}

Json Client::call(const std::string& method, const Json& params) {
  bool done = false;
  boost::system::error_code result;
  Json answer;
  connection_.async_call(method, params, [&](boost::system::error_code ec, Json value) {
    result = ec;
    answer = std::move(value);
    done = true;
  });
  run_until(io_, done);
  if (result.category() == rpc_category()) throw RpcError(method, answer);
  if (result) throw boost::system::system_error(result, method);
  return answer;
}

}  // namespace wheeltec::client
