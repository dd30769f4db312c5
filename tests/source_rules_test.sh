#!/usr/bin/env bash
# tools/source_rules.py on known cases: a scratch repository with each shape the scan must measure
# (or leave alone), and the exact breaches it must print. Usage: source_rules_test.sh SOURCE_DIR
set -euo pipefail
script="$1/tools/source_rules.py"
repo=$(mktemp -d)
trap 'rm -rf "$repo"' EXIT
mkdir -p "$repo/engine" "$repo/shaders" "$repo/docs"

# body N: N lines of statements.
body() { for ((k = 0; k < $1; k++)); do echo "  x += $k;"; done; }

{
  echo "namespace caustica {"
  # 122 lines from its head to its brace: a breach.
  echo "int too_long(int x) {"; body 120; echo "}"
  # 120 lines: within the limit.
  echo "int just_right(int x) {"; body 118; echo "}"
  # Braces inside a raw string, a string, a character and comments are not scopes.
  echo 'const char* kText = R"(a "quoted" } and {'
  echo '} {)";'
  echo 'const char kBrace = '"'}'"'; // }'
  echo '/* { */ const char* kOther = "{";'
  echo "struct Holder {"
  # A constructor whose initializer list has brace members: its body is the function.
  echo "  Holder() : a_{1}, b_(2), c_{{3}} {"; body 120; echo "  }"
  echo "  int a_, b_, c_[1];"
  echo "};"
  echo "}  // namespace caustica"
} > "$repo/engine/cases.cpp"
{
  echo "namespace caustica {"
  # A table of data: an initializer, not a function, however long.
  echo "const int kTable[] = {"; for ((k = 0; k < 130; k++)); do echo "  $k,"; done; echo "};"
  # A function that is a table, marked.
  echo "// source-rules: table"
  echo "int marked_table(int x) {"; body 125; echo "}"
  echo "}  // namespace caustica"
} > "$repo/engine/tables.cpp"
{ echo "void main() {"; body 130; echo "}"; } > "$repo/shaders/long.comp"
for ((k = 0; k < 601; k++)); do echo "// $k"; done > "$repo/engine/long.h"
for ((k = 0; k < 700; k++)); do echo "// $k"; done > "$repo/shaders/just_right.glsl"
echo "See ../""shared/tools for the tool and ORACLES"".md for the numbers." > "$repo/docs/notes.md"
git -C "$repo" init -q && git -C "$repo" add -A

status=0
out=$(python3 "$script" --root "$repo") || status=$?
expected="docs/notes.md:1: cites ../""shared, which is outside the repository
docs/notes.md:1: cites ORACLES"".md, which is outside the repository
engine/cases.cpp:2: function too_long is 122 lines (at most 120)
engine/cases.cpp:249: function Holder is 122 lines (at most 120)
engine/long.h:1: 601 lines (a C++ file has at most 600)
shaders/long.comp:1: function main is 132 lines (at most 120)"
if [[ "$status" != 1 || "$(sort <<< "$out")" != "$(sort <<< "$expected")" ]]; then
  echo "source_rules.py gave (exit $status):"; echo "$out"; echo "expected (exit 1):"; echo "$expected"
  exit 1
fi
report=$(python3 "$script" --root "$repo" --report)
grep -qx "engine: longest file engine/long.h (601 lines); longest function marked_table.*" <<< "$report" && {
  echo "the report counted a marked table as a function: $report"; exit 1; }
grep -qx "engine: longest file engine/long.h (601 lines); longest function too_long at engine/cases.cpp:2 (122 lines)" <<< "$report" || {
  echo "unexpected report: $report"; exit 1; }
git -C "$repo" rm -q --cached docs/notes.md engine/long.h shaders/long.comp
sed -i '/^int too_long/,/^}/d;/^  Holder() :/,/^  }/d' "$repo/engine/cases.cpp"
python3 "$script" --root "$repo" || { echo "source_rules.py found breaches in a clean repository"; exit 1; }
echo "source_rules.py: every known case as expected"
