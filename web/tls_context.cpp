#include "tls_context.hpp"

#include <openssl/err.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <boost/asio/buffer.hpp>
#include <boost/system/system_error.hpp>
#include <fmt/format.h>

#include "wheeltec/config/config_document.hpp"
#include "wheeltec/service/config_file.hpp"

namespace wheeltec::web {

namespace ssl = boost::asio::ssl;

std::shared_ptr<ssl::context> load_tls_context(const TlsFiles& files) {
  std::string cert, key;
  try {
    cert = service::read_config_file(files.cert);
    key = service::read_config_file(files.key, service::ConfigSecrecy::private_);
  } catch (const ConfigError& error) {
    throw ConfigError(fmt::format("TLS: {}", error.what()));
  }
  auto context = std::make_shared<ssl::context>(ssl::context::tls_server);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                       ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  if (SSL_CTX_set_min_proto_version(context->native_handle(), TLS1_2_VERSION) != 1) {
    throw ConfigError("OpenSSL refused TLS 1.2 as the lowest protocol version");
  }
  try {
    context->use_certificate_chain(boost::asio::buffer(cert));
  } catch (const boost::system::system_error& error) {
    throw ConfigError(fmt::format("certificate file {}: not a PEM certificate ({})", files.cert, error.what()));
  }
  const auto mismatch = [&] {
    return ConfigError(fmt::format("key file {} does not belong to the certificate in {}", files.key, files.cert));
  };
  try {
    context->use_private_key(boost::asio::buffer(key), ssl::context::pem);
  } catch (const boost::system::system_error& error) {
    if (ERR_GET_REASON(static_cast<unsigned long>(error.code().value())) == X509_R_KEY_VALUES_MISMATCH) throw mismatch();
    throw ConfigError(fmt::format("key file {}: not a PEM private key ({})", files.key, error.what()));
  }
  if (SSL_CTX_check_private_key(context->native_handle()) != 1) throw mismatch();
  return context;
}

}  // namespace wheeltec::web
