#!/bin/sh
# Fails when a C++ file does not match .clang-format (run `make format` to fix).
set -eu
cd "$(dirname "$0")/.."
files=$(git ls-files '*.h' '*.cpp' 2>/dev/null || find src tests bench examples -name '*.h' -o -name '*.cpp')
clang-format --dry-run --Werror $files
echo "format: ok ($(echo "$files" | wc -w) files)"
