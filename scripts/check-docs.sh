#!/usr/bin/env bash
# The reference pages stay reference (issue #56 item 6): README.md and docs/*.md, except the
# generated docs/RESULTS.md and docs/BENCHMARKS.md; the dated records in docs/experiments/ are not
# reference pages. Fails, naming file and line, when
#   - a reference page holds a date in its text (2026-11-26, Nov 2026, 26 November 2026, ...):
#     measurements are dated in a record, and the page links it. A date inside a link's target is
#     allowed, since records are named by date: [the record](experiments/2026-11-26-foo.md);
#   - docs/ROM.md or docs/TRAINING.md is longer than 300 lines;
#   - a relative link in a reference page points at a file that does not exist, or at a heading
#     (FILE.md#anchor) that the file does not have;
#   - a reference page cites a section of another page by name (docs/ROM.md, "Latent prior") that
#     has no heading (or bold run-in heading) starting so.
# Usage: bash scripts/check-docs.sh [REPO_ROOT]   (default: the repository holding this script)
set -euo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$root"

pages=(README.md)
for f in docs/*.md; do
  case "$f" in docs/RESULTS.md | docs/BENCHMARKS.md) ;; *) pages+=("$f") ;; esac
done

exec python3 - "${pages[@]}" <<'PY'
import os, re, sys

pages = sys.argv[1:]
errors = []
MAX_LINES = {"docs/ROM.md": 300, "docs/TRAINING.md": 300}

MONTH = (r"(?:Jan(?:uary)?|Feb(?:ruary)?|Mar(?:ch)?|Apr(?:il)?|May|June?|July?|Aug(?:ust)?|"
         r"Sep(?:t(?:ember)?)?|Oct(?:ober)?|Nov(?:ember)?|Dec(?:ember)?)")
DATE = re.compile(r"(?<![\w-])(?:(?:19|20)\d\d-(?:0[1-9]|1[0-2])-(?:0[1-9]|[12]\d|3[01])"
                  r"|(?:\d{1,2}\s+)?" + MONTH + r"\.?,?\s+(?:19|20)\d\d)(?![\w-])")
LINK = re.compile(r"\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^()\s>]+(?:\([^()\s]*\)[^()\s>]*)*)>?"
                  r"(?:\s+\"[^\"]*\")?\s*\)")
HEADING = re.compile(r"^#{1,6}\s+(.*?)\s*#*\s*$")
RUN_IN = re.compile(r"^\s*(?:[-*]\s+|\d+\.\s+)?\*\*([^*]+?)\*\*")


def slug(text):
    # GitHub's anchors: lower case, markup and punctuation dropped, spaces to hyphens.
    text = re.sub(r"`|\*|_(?=\W)|(?<=\W)_", "", text.strip().lower())
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    return re.sub(r"[^\w\- ]", "", text).replace(" ", "-")


headings_cache = {}


def headings(path):
    """Section titles of a markdown file: its headings and bold run-in heads, without markup."""
    if path not in headings_cache:
        titles, slugs, seen = [], set(), {}
        fence = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if line.lstrip().startswith("```"):
                    fence = not fence
                    continue
                if fence:
                    continue
                m = HEADING.match(line)
                if m:
                    titles.append(m.group(1))
                    s = slug(m.group(1))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    slugs.add(s if n == 0 else f"{s}-{n}")
                    continue
                m = RUN_IN.match(line)
                if m:
                    titles.append(m.group(1))
        headings_cache[path] = (titles, slugs)
    return headings_cache[path]


def plain(title):
    return re.sub(r"[`*]", "", title).strip()


for page in pages:
    with open(page, encoding="utf-8") as f:
        lines = f.read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    limit = MAX_LINES.get(page)
    if limit is not None and len(lines) > limit:
        errors.append(f"{page}:{len(lines)}: {len(lines)} lines, more than {limit}: a reference "
                      f"page says what each option does; measurements go to docs/experiments/")
    base = os.path.dirname(page)
    fence = False
    for number, line in enumerate(lines, 1):
        if line.lstrip().startswith("```"):
            fence = not fence
        # Dates: in the text, code included, but not in a link's target.
        text = LINK.sub(lambda m: m.group(0)[: m.group(0).rindex("](") + 1], line)
        for m in DATE.finditer(text):
            errors.append(f"{page}:{number}: a date in a reference page: '{m.group(0)}' (move the "
                          f"dated figure to a record in docs/experiments/ and link it)")
        if fence:
            continue
        # Relative links: the file must exist, and a FILE.md#anchor must be one of its headings.
        for m in LINK.finditer(line):
            target = m.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I) or target.startswith("//"):
                continue
            path, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(base, path)) if path else page
            if not os.path.exists(resolved):
                errors.append(f"{page}:{number}: link to '{target}': {resolved} does not exist")
            elif anchor and resolved.endswith(".md") and os.path.isfile(resolved):
                if anchor.lower() not in headings(resolved)[1]:
                    errors.append(f"{page}:{number}: link to '{target}': {resolved} has no "
                                  f"heading with the anchor #{anchor}")

    # Sections cited by name: docs/ROM.md, "Latent prior" (a line break may fall in between).
    joined = LINK.sub(lambda m: m.group(0)[: m.group(0).rindex("](") + 1], "\n".join(lines))
    for m in re.finditer(r"((?:docs/)?[A-Z]+\.md)\]?\)?,?\s+\(?\"([^\"\n]+)\"", joined):
        name, title = m.group(1), m.group(2)
        target = name if name.startswith("docs/") or name == "README.md" else f"docs/{name}"
        if not os.path.isfile(target):
            target = os.path.normpath(os.path.join(base, name))
        if not os.path.isfile(target):
            continue  # a missing file is reported by the link check where it is linked
        wanted = plain(title)
        if not any(plain(t).startswith(wanted) for t in headings(target)[0]):
            number = joined.count("\n", 0, m.start()) + 1
            errors.append(f"{page}:{number}: cites section \"{title}\" of {target}, which has no "
                          f"heading starting so")

for e in errors:
    print(e)
if errors:
    print(f"check-docs: {len(errors)} problem(s) in the reference pages", file=sys.stderr)
    sys.exit(1)
print(f"check-docs: {len(pages)} reference pages: no dates, within their lengths, links resolve")
PY
