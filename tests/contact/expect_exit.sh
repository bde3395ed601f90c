#!/usr/bin/env bash
# expect_exit.sh CODE REGEX COMMAND...: runs COMMAND (stdin closed, 60 s limit) and fails
# unless it exits with CODE and its stderr matches the extended regular expression REGEX.
# For the command-line tests of contact-sim, where ctest alone checks either the exit code
# or the output but not both.
set -u
expected_code=$1 pattern=$2
shift 2
stderr_file=$(mktemp)
trap 'rm -f "$stderr_file"' EXIT
timeout 60 "$@" </dev/null >/dev/null 2>"$stderr_file"
code=$?
if [[ $code -ne $expected_code ]]; then
  echo "expected exit code $expected_code, got $code; stderr:"; cat "$stderr_file"; exit 1
fi
if ! grep -Eq -- "$pattern" "$stderr_file"; then
  echo "stderr does not match '$pattern':"; cat "$stderr_file"; exit 1
fi
echo "exit $code, stderr: $(head -c 300 "$stderr_file")"
