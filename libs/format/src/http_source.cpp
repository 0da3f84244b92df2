#include "terralod/format/http_source.h"

#include <curl/curl.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <mutex>
#include <random>
#include <thread>
#include <vector>

namespace terralod {
namespace {

/// Once per process, on first use. libcurl >= 7.84 makes curl_global_init itself thread-safe
/// (other libraries in the process, GDAL's /vsicurl/ for one, may call it too).
const char* curlGlobalInit() {
  static const CURLcode code = curl_global_init(CURL_GLOBAL_DEFAULT);
  return code == CURLE_OK ? nullptr : curl_easy_strerror(code);
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

/// The URL without "user:password@", for names and messages.
std::string redactCredentials(const std::string& url) {
  const size_t scheme = url.find("://");
  if (scheme == std::string::npos) return url;
  const size_t hostStart = scheme + 3;
  const size_t authorityEnd = std::min(url.find_first_of("/?#", hostStart), url.size());
  const size_t at = url.rfind('@', authorityEnd - 1);
  if (at == std::string::npos || at < hostStart || authorityEnd == hostStart) return url;
  return url.substr(0, hostStart) + url.substr(at + 1);
}

/// Parses "bytes FIRST-LAST/TOTAL" (TOTAL may be "*") or "bytes */TOTAL".
struct ContentRange {
  bool valid = false;
  bool unsatisfied = false;  ///< "bytes */TOTAL"
  uint64_t first = 0, last = 0;
  bool totalKnown = false;
  uint64_t total = 0;
};

bool parseNumber(const std::string& s, uint64_t& out) {
  if (s.empty() || s.size() > 19) return false;
  uint64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + uint64_t(c - '0');
  }
  out = v;
  return true;
}

ContentRange parseContentRange(const std::string& header) {
  ContentRange r;
  const std::string h = lower(trim(header));
  if (h.rfind("bytes ", 0) != 0) return r;
  const std::string spec = trim(h.substr(6));
  const size_t slash = spec.find('/');
  if (slash == std::string::npos) return r;
  const std::string range = spec.substr(0, slash), total = spec.substr(slash + 1);
  if (total != "*") {
    if (!parseNumber(total, r.total)) return r;
    r.totalKnown = true;
  }
  if (range == "*") {
    r.unsatisfied = true;
    r.valid = r.totalKnown;
    return r;
  }
  const size_t dash = range.find('-');
  if (dash == std::string::npos || !parseNumber(range.substr(0, dash), r.first) ||
      !parseNumber(range.substr(dash + 1), r.last) || r.last < r.first)
    return r;
  r.valid = true;
  return r;
}

const char* standardReason(long status) {
  // HTTP/2 and HTTP/3 responses carry no reason phrase.
  switch (status) {
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 408:
      return "Request Timeout";
    case 410:
      return "Gone";
    case 416:
      return "Range Not Satisfiable";
    case 429:
      return "Too Many Requests";
    case 500:
      return "Internal Server Error";
    case 502:
      return "Bad Gateway";
    case 503:
      return "Service Unavailable";
    case 504:
      return "Gateway Timeout";
    default:
      return "";
  }
}

/// One HTTP response as seen by the callbacks. Headers of earlier responses in a redirect chain
/// (or of 1xx interim responses) are dropped when the next status line arrives.
struct Response {
  long status = 0;
  std::string reason;
  std::string contentRange;
  std::string etag;
  std::vector<uint8_t> body;
  uint64_t maxBody = 0;     ///< a 206 body longer than this is aborted
  bool overflow = false;    ///< aborted: more bytes than asked for
  bool notPartial = false;  ///< aborted: a 200 with a body, i.e. ranges are ignored
  std::atomic<uint64_t>* received = nullptr;
};

size_t onHeader(char* data, size_t size, size_t count, void* user) {
  Response& r = *static_cast<Response*>(user);
  const size_t n = size * count;
  const std::string line(data, n);
  if (line.rfind("HTTP/", 0) == 0) {
    r.status = 0;
    r.reason.clear();
    r.contentRange.clear();
    r.etag.clear();
    r.body.clear();
    r.overflow = r.notPartial = false;
    const size_t sp = line.find(' ');
    if (sp != std::string::npos) {
      const std::string rest = trim(line.substr(sp + 1));
      const size_t sp2 = rest.find(' ');
      r.status = std::strtol(rest.substr(0, sp2).c_str(), nullptr, 10);
      if (sp2 != std::string::npos) r.reason = trim(rest.substr(sp2 + 1));
    }
    return n;
  }
  const size_t colon = line.find(':');
  if (colon != std::string::npos) {
    const std::string name = lower(trim(line.substr(0, colon)));
    if (name == "content-range")
      r.contentRange = trim(line.substr(colon + 1));
    else if (name == "etag")
      r.etag = trim(line.substr(colon + 1));
  }
  return n;
}

size_t onBody(char* data, size_t size, size_t count, void* user) {
  Response& r = *static_cast<Response*>(user);
  const size_t n = size * count;
  r.received->fetch_add(n, std::memory_order_relaxed);
  if (r.status == 200) {  // the whole file: do not download it
    r.notPartial = true;
    return 0;
  }
  if (r.status != 206) return n;  // an error page: discarded
  if (r.body.size() + n > r.maxBody) {
    r.overflow = true;
    return 0;
  }
  r.body.insert(r.body.end(), reinterpret_cast<uint8_t*>(data),
                reinterpret_cast<uint8_t*>(data) + n);
  return n;
}

std::string statusText(const Response& r) {
  std::string text = "HTTP " + std::to_string(r.status);
  const std::string reason = r.reason.empty() ? standardReason(r.status) : r.reason;
  return reason.empty() ? text : text + " " + reason;
}

/// Errors no retry can fix.
bool permanentCurlError(CURLcode code) {
  switch (code) {
    case CURLE_UNSUPPORTED_PROTOCOL:
    case CURLE_URL_MALFORMAT:
    case CURLE_NOT_BUILT_IN:
    case CURLE_PEER_FAILED_VERIFICATION:
    case CURLE_SSL_CACERT_BADFILE:
    case CURLE_SSL_CERTPROBLEM:
    case CURLE_SSL_CIPHER:
    case CURLE_SSL_ENGINE_NOTFOUND:
    case CURLE_SSL_ENGINE_SETFAILED:
    case CURLE_SSL_ISSUER_ERROR:
    case CURLE_SSL_PINNEDPUBKEYNOTMATCH:
    case CURLE_SSL_CRL_BADFILE:
    case CURLE_LOGIN_DENIED:
    case CURLE_REMOTE_ACCESS_DENIED:
    case CURLE_TOO_MANY_REDIRECTS:
    case CURLE_BAD_FUNCTION_ARGUMENT:
    case CURLE_BAD_CONTENT_ENCODING:
    case CURLE_OUT_OF_MEMORY:
    case CURLE_FUNCTION_NOT_FOUND:
    case CURLE_UNKNOWN_OPTION:
      return true;
    default:
      return false;
  }
}

enum class Outcome { kOk, kTransient, kPermanent };

struct Attempt {
  Outcome outcome = Outcome::kOk;
  std::string problem;  ///< without the URL
};

/// Easy handles kept for reuse (and with them their keep-alive connections).
class HandlePool {
 public:
  ~HandlePool() {
    for (CURL* h : mFree) curl_easy_cleanup(h);
  }
  CURL* acquire() {
    {
      std::lock_guard lock(mMutex);
      if (!mFree.empty()) {
        CURL* h = mFree.back();
        mFree.pop_back();
        return h;
      }
    }
    return curl_easy_init();
  }
  void release(CURL* h) {
    curl_easy_reset(h);  // keeps live connections and caches
    {
      std::lock_guard lock(mMutex);
      if (mFree.size() < kKeep) {
        mFree.push_back(h);
        return;
      }
    }
    curl_easy_cleanup(h);
  }

 private:
  static constexpr size_t kKeep = 8;
  std::mutex mMutex;
  std::vector<CURL*> mFree;
};

class HttpSource final : public ByteSource {
 public:
  HttpSource(std::string url, std::string name, const HttpOptions& options)
      : mUrl(std::move(url)), mName(std::move(name)), mOptions(options) {}

  uint64_t size() const override { return mSize; }
  const std::string& name() const override { return mName; }
  SourceStats stats() const override {
    return {mBytes.load(), mRequests.load(), mRetries.load(), mFailures.load()};
  }

  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    if (offset > mSize || length > mSize - offset) {
      mFailures.fetch_add(1);
      return makeError(mName, "read of " + std::to_string(length) + " bytes at offset " +
                                  std::to_string(offset) + " is past the end (" +
                                  std::to_string(mSize) + " bytes)");
    }
    if (length == 0) return std::vector<uint8_t>();
    const uint64_t last = offset + length - 1;
    const std::string where = "bytes " + std::to_string(offset) + "-" + std::to_string(last);
    Response response;
    auto checked = withRetries(offset, last, response, where,
                               [&](const Response& r) { return checkPartial(r, offset, last); });
    if (!checked) return checked.error();
    return std::move(response.body);
  }

  /// Learns the size (and ETag) with a ranged GET of byte 0.
  Status probe() {
    Response response;
    auto checked = withRetries(0, 0, response, "", [&](const Response& r) -> Attempt {
      if (r.status == 416) {
        const ContentRange cr = parseContentRange(r.contentRange);
        if (cr.valid && cr.unsatisfied && cr.total == 0) return {};  // an empty file
        return {Outcome::kPermanent,
                "HTTP 416 to a request for byte 0 (Content-Range: '" + r.contentRange + "')"};
      }
      if (r.status == 200 && r.body.empty() && !r.notPartial) return {};  // empty, no ranges
      return checkPartial(r, 0, 0);
    });
    if (!checked) return checked.error();
    if (response.status == 206) {
      mSize = parseContentRange(response.contentRange).total;
      mEtag = response.etag;
    } else {
      mSize = 0;
    }
    return {};
  }

 private:
  /// What a 206 must look like for the range first..last of this resource.
  Attempt checkPartial(const Response& r, uint64_t first, uint64_t last) const {
    if (r.notPartial || r.status == 200)
      return {Outcome::kPermanent,
              "server does not support range requests (HTTP 200 to a range request)"};
    if (r.status != 206) return {Outcome::kPermanent, statusText(r) + " to a range request"};
    const ContentRange cr = parseContentRange(r.contentRange);
    if (!cr.valid || cr.unsatisfied || !cr.totalKnown)
      return {Outcome::kPermanent,
              "HTTP 206 without a usable Content-Range ('" + r.contentRange + "')"};
    if (mSize != kUnknown && cr.total != mSize)
      return {Outcome::kPermanent, "changed on the server: was " + std::to_string(mSize) +
                                       " bytes, now " + std::to_string(cr.total)};
    if (!mEtag.empty() && !r.etag.empty() && r.etag != mEtag)
      return {Outcome::kPermanent, "changed on the server: ETag was " + mEtag + ", now " + r.etag};
    if (cr.first != first)
      return {Outcome::kPermanent, "server sent the wrong range (" + r.contentRange + ")"};
    const uint64_t want = last - first + 1;
    if (r.overflow)
      return {Outcome::kTransient,
              "server sent more than the " + std::to_string(want) + " bytes asked for"};
    if (r.body.size() != want)
      return {Outcome::kTransient, "short body: " + std::to_string(r.body.size()) + " of " +
                                       std::to_string(want) + " bytes"};
    return {};
  }

  /// One request, classified. `check` judges a response that arrived with a status below 300.
  template <typename Check>
  Attempt once(uint64_t first, uint64_t last, Response& r, const Check& check) const {
    CURL* h = mHandles.acquire();
    if (!h) return {Outcome::kTransient, "curl_easy_init failed"};
    char errorBuffer[CURL_ERROR_SIZE] = {};
    const std::string range = std::to_string(first) + "-" + std::to_string(last);
    r = Response();
    r.maxBody = last - first + 1;
    r.received = &mBytes;
    r.body.reserve(size_t(last - first + 1));
    curl_easy_setopt(h, CURLOPT_URL, mUrl.c_str());
    curl_easy_setopt(h, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(h, CURLOPT_REDIR_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(h, CURLOPT_FOLLOWLOCATION, 1L);
    curl_easy_setopt(h, CURLOPT_MAXREDIRS, 5L);
    curl_easy_setopt(h, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(h, CURLOPT_TCP_KEEPALIVE, 1L);
    curl_easy_setopt(h, CURLOPT_USERAGENT, "terralod");
    curl_easy_setopt(h, CURLOPT_RANGE, range.c_str());
    curl_easy_setopt(h, CURLOPT_ERRORBUFFER, errorBuffer);
    curl_easy_setopt(h, CURLOPT_HEADERFUNCTION, onHeader);
    curl_easy_setopt(h, CURLOPT_HEADERDATA, &r);
    curl_easy_setopt(h, CURLOPT_WRITEFUNCTION, onBody);
    curl_easy_setopt(h, CURLOPT_WRITEDATA, &r);
    const auto ms = [](double seconds) { return long(std::max(1.0, std::ceil(seconds * 1000))); };
    if (mOptions.connectTimeoutSeconds > 0)
      curl_easy_setopt(h, CURLOPT_CONNECTTIMEOUT_MS, ms(mOptions.connectTimeoutSeconds));
    if (mOptions.requestTimeoutSeconds > 0)
      curl_easy_setopt(h, CURLOPT_TIMEOUT_MS, ms(mOptions.requestTimeoutSeconds));
    if (mOptions.lowSpeedBytesPerSecond > 0 && mOptions.lowSpeedSeconds > 0) {
      curl_easy_setopt(h, CURLOPT_LOW_SPEED_LIMIT, mOptions.lowSpeedBytesPerSecond);
      curl_easy_setopt(h, CURLOPT_LOW_SPEED_TIME,
                       long(std::max(1.0, std::ceil(mOptions.lowSpeedSeconds))));
    }
    mRequests.fetch_add(1);
    const CURLcode code = curl_easy_perform(h);
    mHandles.release(h);

    if (code != CURLE_OK) {
      if (code == CURLE_WRITE_ERROR && (r.notPartial || r.overflow)) return check(r);
      std::string detail = errorBuffer[0] ? errorBuffer : curl_easy_strerror(code);
      detail = trim(detail);
      std::replace(detail.begin(), detail.end(), '\n', ' ');
      return {permanentCurlError(code) ? Outcome::kPermanent : Outcome::kTransient, detail};
    }
    // 416 is the answer for an empty file: the check decides. 408 and 429 are worth a retry
    // like 5xx; any other 4xx (and a redirect not followed) is final.
    if (r.status == 416 || (r.status >= 200 && r.status < 300)) return check(r);
    const bool transient = r.status >= 500 || r.status == 408 || r.status == 429;
    return {transient ? Outcome::kTransient : Outcome::kPermanent, statusText(r)};
  }

  template <typename Check>
  Status withRetries(uint64_t first, uint64_t last, Response& r, const std::string& where,
                     const Check& check) const {
    Attempt a;
    int attempt = 0;
    for (;; ++attempt) {
      a = once(first, last, r, check);
      if (a.outcome != Outcome::kTransient || attempt >= mOptions.retries) break;
      mRetries.fetch_add(1);
      std::this_thread::sleep_for(std::chrono::duration<double>(backoff(attempt)));
    }
    if (a.outcome == Outcome::kOk) return {};
    mFailures.fetch_add(1);
    std::string context = where;
    if (attempt > 0)
      context += (context.empty() ? "" : ", ") + std::string("gave up after ") +
                 std::to_string(attempt) + (attempt == 1 ? " retry" : " retries");
    return makeError(mName, a.problem + (context.empty() ? "" : " (" + context + ")"));
  }

  /// The wait before retry number `attempt` + 1: doubling from the first backoff, capped, and
  /// drawn between half and all of that so that many clients do not retry in lockstep.
  double backoff(int attempt) const {
    const double nominal = std::min(mOptions.maxBackoffSeconds,
                                    mOptions.firstBackoffSeconds * std::ldexp(1.0, attempt));
    thread_local std::minstd_rand random{std::random_device{}()};
    return std::max(0.0, nominal) * std::uniform_real_distribution<double>(0.5, 1.0)(random);
  }

  static constexpr uint64_t kUnknown = ~uint64_t(0);
  std::string mUrl;
  std::string mName;
  HttpOptions mOptions;
  uint64_t mSize = kUnknown;
  std::string mEtag;
  mutable HandlePool mHandles;
  mutable std::atomic<uint64_t> mBytes{0}, mRequests{0}, mRetries{0}, mFailures{0};
};

}  // namespace

bool isHttpUrl(const std::string& pathOrUrl) {
  const std::string head = lower(pathOrUrl.substr(0, 8));
  return head.rfind("http://", 0) == 0 || head.rfind("https://", 0) == 0;
}

Result<std::unique_ptr<ByteSource>> openHttpSource(const std::string& url,
                                                   const HttpOptions& options) {
  const std::string name = redactCredentials(url);
  if (!isHttpUrl(url)) return makeError(name, "not an http:// or https:// URL");
  if (const char* problem = curlGlobalInit())
    return makeError(name, std::string("cannot initialise libcurl: ") + problem);
  auto source = std::make_unique<HttpSource>(url, name, options);
  if (Status s = source->probe(); !s) return s.error();
  return std::unique_ptr<ByteSource>(std::move(source));
}

Result<std::unique_ptr<ByteSource>> openByteSource(const std::string& pathOrUrl) {
  if (isHttpUrl(pathOrUrl)) return openHttpSource(pathOrUrl);
  return openFileSource(pathOrUrl);
}

}  // namespace terralod
