#pragma once
// NTRIP credentials kept out of the ROS parameter server, the command line and the
// launch log. An ntrip:// spec (io/transport/byte_source_spec.h) gets its user and password,
// in this order, from
//   1. the spec itself (ntrip://user:password@host/MOUNT): works, but the password is
//      then wherever the spec is (rosparam, the roslaunch log): warned;
//   2. the option credentials=PATH: a file holding one line "user:password" (the first
//      line that is neither empty nor a '#' comment; the password is everything after
//      the first ':', taken as written, no percent-decoding). Like ssh keys and
//      .netrc, the file must be a regular file that only its owner can read and write
//      (mode 0600 or 0400): a file that its group or others may read or write is
//      refused, naming the file and its mode;
//   3. the environment variable PPP_NTRIP_CREDENTIALS="user:password" (same syntax),
//      when the spec has neither a password nor credentials=.
// From the file and the variable alike, trailing CR and LF characters are removed
// (a line written on Windows), and an empty password ("alice:") is refused.
// A user given in the spec must match the user of the file or the variable.
// Errors are ByteSourceSpecError naming the spec (masked), the file or the variable,
// never the password.
#include <string>

#include "ppp_bayes_tree/io/transport/byte_source_spec.h"

namespace ppp {

extern const char* const kNtripCredentialsEnvironment;  // "PPP_NTRIP_CREDENTIALS"

enum class CredentialSource { None, Spec, File, Environment };
/// "none", "the spec (visible where the spec is)", "the file ...", "the environment variable ...".
std::string credentialSourceText(CredentialSource source);

/// Fills spec.user and spec.password of an ntrip spec from its credentials file or
/// `environment_value` (the variable's value, nullptr when unset) as above; other
/// kinds are left alone (None). Throws ByteSourceSpecError.
CredentialSource resolveNtripCredentials(ByteSourceSpec& spec, const char* environment_value);

}  // namespace ppp
