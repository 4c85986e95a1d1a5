#pragma once

// The programs of the fleet under measurement: one mosquitto broker on 127.0.0.1, and per
// robot a wheeltec-emu, a wheeltecd and a wheeltec-mqtt on its own vcan interface, each
// with its files (configuration, socket, log) in a directory of its own. A robot may have its
// chassis on a serial line instead, whose other end the benchmark plays: no emulator then.

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "child_program.hpp"

namespace bench {

struct FleetPrograms {
  std::string wheeltecd;
  std::string emulator;
  std::string bridge;
  std::string mosquitto = "/usr/sbin/mosquitto";
  std::string paho_bridge;  // bench/mqtt/paho_bridge.py, run by python
  std::string python = "/usr/bin/python3";
};

class Broker {
 public:
  // Starts mosquitto on a free port of 127.0.0.1 (anonymous, no persistence, and the
  // `extra_config` lines) and waits until it accepts connections.
  Broker(const std::string& mosquitto, const std::filesystem::path& directory,
         const std::vector<std::string>& extra_config = {});
  int port() const { return port_; }
  // SIGKILL; returns CLOCK_REALTIME (ns) taken just before kill(). Not reaped here: reaping
  // sleeps in steps of 10 ms, and a frame read from a pty meanwhile would be timed late.
  std::int64_t kill();
  // Reaps it, starts it again on the same port with the same configuration, and waits as at start-up.
  void restart();
  pid_t pid() const { return process_->pid(); }
  bool running() { return process_->running(); }
  std::string log_tail() const { return process_->log_tail(); }

 private:
  void start();

  std::string mosquitto_;
  std::filesystem::path directory_;
  int port_;
  std::unique_ptr<ChildProgram> process_;
};

struct CanLink {
  std::string interface;  // with a wheeltec-emu on it
};
struct SerialLink {
  std::filesystem::path device;  // a pty's slave, published by the benchmark that plays the controller
};
using ChassisLink = std::variant<CanLink, SerialLink>;

class Robot {
 public:
  Robot(const FleetPrograms& programs, std::filesystem::path directory, std::string name, ChassisLink link);
  void start_emulator();  // CAN only
  void start_daemon();  // returns once its socket accepts connections
  void start_bridge(int broker_port);
  // The Python reference bridge on the same daemon, with topics under PREFIX/`robot`.
  void start_paho_bridge(int broker_port, const std::string& robot);

  const std::string& name() const { return name_; }
  const std::string& interface() const { return interface_; }  // CAN only; empty on a serial line
  const std::filesystem::path& socket() const { return socket_; }
  ChildProgram& emulator() { return *emulator_; }
  ChildProgram& daemon() { return *daemon_; }
  ChildProgram& bridge() { return *bridge_; }
  ChildProgram& paho_bridge() { return *paho_bridge_; }
  // Which of its programs are not running (empty: all are).
  std::vector<std::string> ended();
  std::string logs() const;

 private:
  FleetPrograms programs_;
  std::filesystem::path directory_;
  std::string name_;
  std::string interface_;
  std::filesystem::path socket_;
  std::unique_ptr<ChildProgram> emulator_;
  std::unique_ptr<ChildProgram> daemon_;
  std::unique_ptr<ChildProgram> bridge_;
  std::unique_ptr<ChildProgram> paho_bridge_;
};

}  // namespace bench
