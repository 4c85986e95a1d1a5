#pragma once

// Socket options as small types, for socket.set_option() and get_option(): Boost.Asio's
// SettableSocketOption and GettableSocketOption requirements, without its detail namespace.

#include <cstddef>
#include <stdexcept>

namespace wheeltec::asio_can::option {

// An option at (Level, Name) that the kernel takes and gives as an int.
template <int Level, int Name>
class int_valued {
 public:
  template <class Protocol> int level(const Protocol&) const noexcept { return Level; }
  template <class Protocol> int name(const Protocol&) const noexcept { return Name; }
  template <class Protocol> int* data(const Protocol&) noexcept { return &value_; }
  template <class Protocol> const int* data(const Protocol&) const noexcept { return &value_; }
  template <class Protocol> std::size_t size(const Protocol&) const noexcept { return sizeof(value_); }

 protected:
  int value_ = 0;
};

template <int Level, int Name>
class integer : public int_valued<Level, Name> {
 public:
  integer() noexcept = default;
  explicit integer(int value) noexcept { this->value_ = value; }

  int value() const noexcept { return this->value_; }

  template <class Protocol> void resize(const Protocol&, std::size_t size) {
    if (size != sizeof(int)) throw std::length_error("integer socket option resize");
  }
};

template <int Level, int Name>
class boolean : public int_valued<Level, Name> {
 public:
  boolean() noexcept = default;
  explicit boolean(bool value) noexcept { this->value_ = value ? 1 : 0; }

  bool value() const noexcept { return this->value_ != 0; }
  explicit operator bool() const noexcept { return value(); }

  // Some kernels answer getsockopt with one byte for a boolean.
  template <class Protocol> void resize(const Protocol&, std::size_t size) {
    if (size == sizeof(char)) {
      this->value_ = *reinterpret_cast<const unsigned char*>(&this->value_) ? 1 : 0;
    } else if (size != sizeof(int)) {
      throw std::length_error("boolean socket option resize");
    }
  }
};

}  // namespace wheeltec::asio_can::option
