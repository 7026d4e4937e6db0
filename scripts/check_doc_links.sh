#!/usr/bin/env bash
# scripts/check_doc_links.sh ROOT: every relative Markdown link `[text](target)` in ROOT/README.md and
# ROOT/docs/**/*.md must name an existing file or folder (resolved from the linking page's folder; a
# `#anchor` suffix is ignored; http(s):// and mailto: links are not checked). Prints one line per broken
# link ("page: target") and exits 1 when there is any, 2 on bad usage, 0 otherwise.
set -u
root="${1:-}"
if [[ -z "$root" || ! -d "$root" ]]; then
    echo "usage: check_doc_links.sh ROOT (the source tree holding README.md and docs/)" >&2
    exit 2
fi
cd "$root" || exit 2
broken=0
checked=0
while IFS= read -r -d '' page; do
    dir=$(dirname "$page")
    # Every `](target)`; fenced code blocks are skipped.
    while IFS= read -r target; do
        [[ -z "$target" ]] && continue
        case "$target" in
            http://*|https://*|mailto:*|\#*) continue ;;
        esac
        path="${target%%#*}"
        checked=$((checked + 1))
        if [[ ! -e "$dir/$path" ]]; then
            echo "$page: broken link: $target"
            broken=$((broken + 1))
        fi
    done < <(awk '/^```/ { fence = !fence; next } !fence' "$page" | grep -o '\](\([^)[:space:]]*\))' | sed 's/^](//; s/)$//')
done < <(find README.md docs -name '*.md' -print0 2>/dev/null)
if (( checked == 0 )); then
    echo "check_doc_links.sh: no links found under $root (README.md, docs/)" >&2
    exit 1
fi
if (( broken > 0 )); then
    echo "$broken broken link(s) of $checked" >&2
    exit 1
fi
echo "$checked links resolve"
