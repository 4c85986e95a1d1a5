#pragma once

// The server's TLS settings from its certificate and key files (spec section 6, TLS):
// TLS 1.2 or later only; the key file must not be readable by others.

#include <memory>
#include <string>

#include <boost/asio/ssl/context.hpp>

namespace wheeltec::web {

struct TlsFiles {
  std::string cert;  // PEM: the server's certificate, then any intermediates
  std::string key;   // PEM: its private key
};

// Throws ConfigError naming the file: unreadable, readable by others (the key), not PEM,
// or a key that does not belong to the certificate.
std::shared_ptr<boost::asio::ssl::context> load_tls_context(const TlsFiles& files);

}  // namespace wheeltec::web
