#include "ppp_bayes_tree/io/transport/ntrip_credentials.h"

#include <sys/stat.h>

#include <cstdio>
#include <fstream>

namespace ppp {
namespace {

[[noreturn]] void refuse(const ByteSourceSpec& spec, const std::string& why) {
  throw ByteSourceSpecError("input spec '" + spec.text_without_password + "': " + why);
}

struct UserPassword {
  std::string user, password;
};

/// The line without its line end: every trailing CR and LF (a file or a variable
/// written on Windows, `export VAR="$(cat file)"`), the same for both sources.
std::string withoutLineEnd(std::string line) {
  while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
  return line;
}

/// "user:password" of `origin` (a file line or the variable), its line end removed;
/// refused without a user, a ':' or a password (the password is never named).
UserPassword splitUserPassword(const ByteSourceSpec& spec, const std::string& text, const std::string& origin) {
  const std::string line = withoutLineEnd(text);
  const auto colon = line.find(':');
  if (colon == std::string::npos || colon == 0)
    refuse(spec, origin + " must hold user:password (a user, a ':' and the password)");
  if (colon + 1 == line.size())
    refuse(spec, origin + " holds an empty password (user:password with nothing after the ':')");
  return {line.substr(0, colon), line.substr(colon + 1)};
}

std::string octalMode(mode_t mode) {
  char text[8];
  std::snprintf(text, sizeof text, "%04o", static_cast<unsigned>(mode & 07777));
  return text;
}

UserPassword readCredentialsFile(const ByteSourceSpec& spec, const std::string& path) {
  struct stat st {};
  const std::string origin = "the credentials file " + path;
  if (::stat(path.c_str(), &st) != 0) refuse(spec, origin + " does not exist or cannot be read");
  if (!S_ISREG(st.st_mode)) refuse(spec, origin + " is not a regular file");
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0)
    refuse(spec, origin + " has mode " + octalMode(st.st_mode) +
                     ": its group or others may read or write it; make it readable by its owner only "
                     "(chmod 600 " + path + ")");
  std::ifstream in(path);
  if (!in) refuse(spec, origin + " cannot be read");
  std::string line;
  while (std::getline(in, line)) {
    line = withoutLineEnd(line);
    if (line.empty() || line[0] == '#') continue;
    return splitUserPassword(spec, line, origin);
  }
  refuse(spec, origin + " holds no user:password line");
}

void apply(ByteSourceSpec& spec, const UserPassword& given, const std::string& origin) {
  if (!spec.user.empty() && spec.user != given.user)
    refuse(spec, "the user of the spec differs from the user of " + origin);
  spec.user = given.user;
  spec.password = given.password;
}

}  // namespace

const char* const kNtripCredentialsEnvironment = "PPP_NTRIP_CREDENTIALS";

std::string credentialSourceText(CredentialSource source) {
  switch (source) {
    case CredentialSource::None: return "none";
    case CredentialSource::Spec: return "the spec (visible wherever the spec is: rosparam, the launch log)";
    case CredentialSource::File: return "the credentials file";
    case CredentialSource::Environment: return std::string("the environment variable ") + kNtripCredentialsEnvironment;
  }
  return "none";
}

CredentialSource resolveNtripCredentials(ByteSourceSpec& spec, const char* environment_value) {
  if (spec.kind != ByteSourceKind::Ntrip) return CredentialSource::None;
  if (!spec.credentials_file.empty()) {
    if (!spec.password.empty()) refuse(spec, "a password in the spec and credentials= as well: give one of them");
    apply(spec, readCredentialsFile(spec, spec.credentials_file), "the credentials file " + spec.credentials_file);
    return CredentialSource::File;
  }
  if (!spec.password.empty()) return CredentialSource::Spec;
  if (environment_value && *environment_value) {
    const std::string origin = std::string("the environment variable ") + kNtripCredentialsEnvironment;
    apply(spec, splitUserPassword(spec, environment_value, origin), origin);
    return CredentialSource::Environment;
  }
  return CredentialSource::None;
}

}  // namespace ppp
