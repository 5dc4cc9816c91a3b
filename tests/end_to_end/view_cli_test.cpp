// `rbpart view` as a user runs it: a port another viewer holds is refused, naming it (issue #26:
// with SO_REUSEPORT both bound and connections went to either at random).
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/cli_test.hpp"

namespace {

class ViewCli : public rbpart::test::CliTest {};

TEST_F(ViewCli, RefusesAPortAnotherListenerHolds) {
  // A stand-in viewer: listening on 127.0.0.1 with SO_REUSEPORT, as httplib's default sets it.
  const int holder = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(holder, 0);
  const int yes = 1;
  ASSERT_EQ(::setsockopt(holder, SOL_SOCKET, SO_REUSEPORT, &yes, sizeof yes), 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(holder, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(::listen(holder, 1), 0);
  socklen_t length = sizeof address;
  ASSERT_EQ(::getsockname(holder, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const std::string port = std::to_string(ntohs(address.sin_port));

  // The viewer's files only need to exist for the port to be tried.
  std::filesystem::create_directories(path("viewer"));
  for (const char* file : {"index.html", "viewer.js", "viewer.css"}) write("viewer/" + std::string(file), "");
  ::setenv("RBPART_VIEWER_DIR", path("viewer").c_str(), 1);
  ASSERT_EQ(run("simulate --scene box_stack --steps 2 -q --record " + path("r.rbrec")).status, 0);
  // Bound anyway, it would serve until the timeout (status 124).
  const Result r = run("view " + path("r.rbrec") + " --port " + port, "timeout 20 ");
  ::unsetenv("RBPART_VIEWER_DIR");
  ::close(holder);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err, "rbpart: error: --port " + port + ": 127.0.0.1:" + port +
                       " is already in use (another rbpart view?); choose another port\n");
}

}  // namespace
