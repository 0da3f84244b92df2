#pragma once
// A real HTTP server for tests: nginx (Debian's package, /usr/sbin/nginx, from
// scripts/install-deps.sh) serving a directory on 127.0.0.1 at a free port, run as a child
// process with its configuration, logs, pid file and temp directories in a TempDir.
//
//   /            the directory, with range requests
//   /status500/  every request answers 500
//   /reset/      nginx closes the connection without a response (`return 444`)
//   /slow/       the directory again, at `limit_rate` 2 KB/s per connection
//   /noranges/   the directory again, ignoring Range (`max_ranges 0`: always 200, whole file)
//
// nginx runs in the foreground as a single process (`master_process off`, `daemon off`): one
// pid to stop, no worker to orphan, no `user` switch (as root it stays root and reads the test's
// 0700 temp directories; as any other user it needs no privilege, the port being > 1024). If the
// test process dies the kernel sends nginx SIGTERM (PR_SET_PDEATHSIG).
//
// Usage:  NginxServer server(dir.path());
//         ASSERT_TRUE(server.running()) << server.error();
//         server.url("gully.tlod");  // http://127.0.0.1:PORT/gully.tlod
//         server.stop();             // SIGTERM, SIGKILL after 5 s, reaped
//         server.start();            // again, on the same port

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.h"

namespace terralod::test {

class NginxServer {
 public:
  /// Starts serving `root`; `port` 0 picks a free one. Check running() and error().
  explicit NginxServer(std::filesystem::path root, int port = 0)
      : mRoot(std::filesystem::absolute(std::move(root))), mPort(port) {
    const bool pickPort = mPort == 0;
    for (int attempt = 0; attempt < 5; ++attempt) {
      if (pickPort) mPort = freePort();
      if (mPort <= 0) {
        mError = "no free port on 127.0.0.1";
        return;
      }
      if (start() || !pickPort) return;
      // Another process may have taken the port between our probe and nginx's bind.
      if (mError.find("Address already in use") == std::string::npos) return;
    }
  }
  ~NginxServer() { stop(); }
  NginxServer(const NginxServer&) = delete;
  NginxServer& operator=(const NginxServer&) = delete;

  bool running() const { return mPid > 0; }
  int port() const { return mPort; }
  /// Why the last start() failed.
  const std::string& error() const { return mError; }
  /// http://127.0.0.1:PORT/ followed by `path` (no leading slash).
  std::string url(const std::string& path = "") const {
    return "http://127.0.0.1:" + std::to_string(mPort) + "/" + path;
  }
  const std::filesystem::path& prefix() const { return mPrefix.path(); }

  /// (Re)starts on port(), waiting (at most 10 s) until it accepts connections.
  bool start() {
    stop();
    mError.clear();
    const std::string nginx = nginxBinary();
    if (nginx.empty()) {
      mError = "nginx not found (/usr/sbin/nginx); scripts/install-deps.sh installs it";
      return false;
    }
    std::filesystem::remove(pidFile());
    writeConfig();
    const std::string prefixArg = mPrefix.path().string() + "/";
    const std::string confArg = mPrefix.file("nginx.conf");
    const std::string errorLogArg = mPrefix.file("error.log");
    const std::string outArg = mPrefix.file("stderr.log");
    std::vector<std::string> args = {nginx, "-p",        prefixArg, "-c",         confArg,
                                     "-e",  errorLogArg, "-g",      "daemon off;"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid < 0) {
      mError = "fork failed";
      return false;
    }
    if (pid == 0) {  // only async-signal-safe calls until exec
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(126);
      const int in = open("/dev/null", O_RDONLY);
      const int out = open(outArg.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
      if (in >= 0) dup2(in, STDIN_FILENO);
      if (out >= 0) {
        dup2(out, STDOUT_FILENO);
        dup2(out, STDERR_FILENO);
      }
      execv(argv[0], argv.data());
      _exit(127);
    }
    mPid = pid;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (waitpid(mPid, &status, WNOHANG) == mPid) {
        mPid = -1;
        mError = "nginx exited at startup (" + describe(status) + "): " + logs();
        return false;
      }
      if (std::filesystem::exists(pidFile()) && accepts(mPort)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    stop();
    mError = "nginx did not accept connections on port " + std::to_string(mPort) +
             " within 10 s: " + logs();
    return false;
  }

  /// Stops the server (SIGTERM; SIGKILL if it is still there after 5 s) and reaps it.
  void stop() {
    if (mPid <= 0) return;
    kill(mPid, SIGTERM);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      const pid_t r = waitpid(mPid, &status, WNOHANG);
      if (r == mPid || r < 0) {
        mPid = -1;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    kill(mPid, SIGKILL);
    waitpid(mPid, &status, 0);
    mPid = -1;
  }

  std::string errorLog() const { return readFile(mPrefix.file("error.log")); }
  std::string accessLog() const { return readFile(mPrefix.file("access.log")); }
  /// Access log lines (format: "$request_uri $status $http_range") that contain `needle`.
  /// nginx logs a request after it has sent the response, so the client may be done before the
  /// last line is written: this waits (at most 2 s) until there are at least `atLeast` lines,
  /// then 100 ms more for any stragglers, and returns the count.
  size_t requestsFor(const std::string& needle, size_t atLeast = 1) const {
    const auto count = [&] {
      std::istringstream in(accessLog());
      size_t n = 0;
      for (std::string line; std::getline(in, line);)
        if (line.find(needle) != std::string::npos) ++n;
      return n;
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    while (count() < atLeast && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    return count();
  }

 private:
  static std::string nginxBinary() {
    for (const char* candidate : {"/usr/sbin/nginx", "/usr/local/sbin/nginx", "/usr/bin/nginx"})
      if (access(candidate, X_OK) == 0) return candidate;
    return "";
  }

  static int freePort() {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    socklen_t length = sizeof address;
    int port = -1;
    if (bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
        getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0)
      port = ntohs(address.sin_port);
    close(fd);
    return port;
  }

  static bool accepts(int port) {
    const int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(uint16_t(port));
    const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
    close(fd);
    return ok;
  }

  static std::string describe(int status) {
    if (WIFEXITED(status)) return "exit code " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
    return "status " + std::to_string(status);
  }

  static std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }

  std::string pidFile() const { return mPrefix.file("nginx.pid"); }
  std::string logs() const {
    std::string text = readFile(mPrefix.file("stderr.log")) + errorLog();
    for (char& c : text)
      if (c == '\n') c = ' ';
    return text;
  }

  static std::string quoted(const std::filesystem::path& p) { return "\"" + p.string() + "\""; }

  void writeConfig() const {
    const auto& dir = mPrefix.path();
    std::filesystem::create_directories(dir / "temp");
    const std::string root = mRoot.string() + "/";
    std::ofstream conf(mPrefix.file("nginx.conf"));
    conf << "master_process off;\n"
         << "worker_processes 1;\n"
         << "pid " << quoted(dir / "nginx.pid") << ";\n"
         << "error_log " << quoted(dir / "error.log") << " info;\n"
         << "events { worker_connections 256; }\n"
         << "http {\n"
         << "  log_format tests '$request_uri $status $http_range';\n"
         << "  access_log " << quoted(dir / "access.log") << " tests;\n"
         << "  client_body_temp_path " << quoted(dir / "temp/body") << ";\n"
         << "  proxy_temp_path " << quoted(dir / "temp/proxy") << ";\n"
         << "  fastcgi_temp_path " << quoted(dir / "temp/fastcgi") << ";\n"
         << "  uwsgi_temp_path " << quoted(dir / "temp/uwsgi") << ";\n"
         << "  scgi_temp_path " << quoted(dir / "temp/scgi") << ";\n"
         << "  default_type application/octet-stream;\n"
         << "  sendfile on;\n"
         << "  keepalive_timeout 30s;\n"
         << "  server {\n"
         << "    listen 127.0.0.1:" << mPort << ";\n"
         << "    server_name localhost;\n"
         << "    root " << quoted(mRoot) << ";\n"
         << "    location / { }\n"
         << "    location /status500/ { return 500; }\n"
         << "    location /reset/ { return 444; }\n"
         << "    location /slow/ { alias \"" << root << "\"; limit_rate 2k; }\n"
         << "    location /noranges/ { alias \"" << root << "\"; max_ranges 0; }\n"
         << "  }\n"
         << "}\n";
  }

  std::filesystem::path mRoot;
  int mPort = 0;
  TempDir mPrefix;
  pid_t mPid = -1;
  std::string mError;
};

}  // namespace terralod::test
