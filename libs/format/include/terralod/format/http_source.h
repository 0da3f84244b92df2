#pragma once
// A ByteSource over HTTP or HTTPS (libcurl): every read() is one `Range: bytes=a-b` GET.
//
// Opening issues one ranged GET of byte 0 and takes the size from its Content-Range, so it also
// proves that the server honours ranges: a server that answers a ranged request with 200 and the
// whole body is refused ("server does not support range requests") without downloading it.
// A read checks for 206, a Content-Range that is the range asked for, the size and ETag seen at
// opening (a file replaced on the server fails instead of mixing two versions) and the exact
// body length.
//
// Transient failures — connection errors and resets, timeouts, stalls, 5xx, 408, 429, short or
// long bodies — are retried up to `retries` times with exponential backoff (with jitter) from
// `firstBackoffSeconds`, doubling, capped at `maxBackoffSeconds`. Other 4xx fail at once. Every
// error is one line that starts with the URL, e.g. "http://host/a.tlod: HTTP 404 Not Found".
// Credentials in the URL (user:password@) are sent but never appear in name() or messages.
//
// Thread-safe: concurrent reads take CURL easy handles from a small mutex-protected pool, so
// sequential reads reuse their keep-alive connections. curl_global_init runs once, on first use.

#include <memory>
#include <string>

#include "terralod/format/byte_source.h"

namespace terralod {

struct HttpOptions {
  int retries = 4;  ///< further attempts after the first one fails transiently
  double firstBackoffSeconds = 0.2;
  double maxBackoffSeconds = 5;
  double connectTimeoutSeconds = 5;
  double requestTimeoutSeconds = 30;  ///< whole request, headers and body
  /// A transfer slower than this many bytes per second for lowSpeedSeconds is aborted (and
  /// retried): catches stalled connections long before the request timeout. 0 disables.
  long lowSpeedBytesPerSecond = 1;
  double lowSpeedSeconds = 10;
};

/// Opens `url` (http:// or https://) for range reads; learns its size with one request
/// (retried like reads). stats() counts this request too.
Result<std::unique_ptr<ByteSource>> openHttpSource(const std::string& url,
                                                   const HttpOptions& options = {});

/// True for http:// and https:// URLs (scheme case-insensitive).
bool isHttpUrl(const std::string& pathOrUrl);

/// http:// and https:// go to openHttpSource (default options), everything else to
/// openFileSource.
Result<std::unique_ptr<ByteSource>> openByteSource(const std::string& pathOrUrl);

}  // namespace terralod
