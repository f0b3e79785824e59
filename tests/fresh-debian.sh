#!/usr/bin/env bash
# The check for any change to the install steps: runs a command of this checkout inside a
# minimal Debian 12 root (debootstrap --variant=minbase) that starts with nothing but the
# repository, as a new user's machine would.
#
#   sudo ./tests/fresh-debian.sh                 ./tests/run.sh, then a short ./deploy/run.sh
#   sudo ./tests/fresh-debian.sh 'COMMAND'       any command, run from the checkout's copy
#
# The pristine root is made once and cached as a tarball (SRICS_FRESH_CACHE, default
# /var/cache/srics-fresh-debian); every run unpacks a new copy of it, so nothing installed
# by an earlier run is there. The apt sources are read from this machine's own apt
# configuration (no mirror address lives in the repository). Timings of each phase are
# printed at the end and written to fresh-debian-times.txt in the work folder.
#   SRICS_FRESH_KEEP=1   keep the work folder (the used root) after the run
#   SRICS_FRESH_WORK     where the root is unpacked (default /var/tmp/srics-fresh-debian)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cache=${SRICS_FRESH_CACHE:-/var/cache/srics-fresh-debian}
work=${SRICS_FRESH_WORK:-/var/tmp/srics-fresh-debian}
suite=bookworm
default_command='./tests/run.sh && ./deploy/run.sh tests/integration/system-test.yaml --set run.name=fresh-debian --display plain'
command=${1:-$default_command}

die() { echo "fresh-debian: $*" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap and chroot): run it with sudo"
[ "$(uname -m)" = x86_64 ] || echo "fresh-debian: note: not x86_64, the root is made for $(dpkg --print-architecture)"

# --- the mirror this machine already uses, from its apt configuration -----------------
mirror_of_host() {
  local f uri
  # deb822 sources: the URIs of a stanza whose Suites hold the release itself
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    uri=$(awk -v s="$suite" '
      /^[[:space:]]*$/ { if (u != "" && hit) { print u; exit } u=""; hit=0; next }
      /^URIs:/ { u=$2 }
      /^Suites:/ { for (i = 2; i <= NF; i++) if ($i == s) hit=1 }
      END { if (u != "" && hit) print u }' "$f" | head -1)
    [ -n "$uri" ] && { echo "$uri"; return; }
  done
  # one-line sources
  for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -f "$f" ] || continue
    uri=$(awk -v s="$suite" '$1 == "deb" && $3 == s { print $2; exit }' "$f")
    [ -n "$uri" ] && { echo "$uri"; return; }
  done
}

tarball=$cache/$suite-minbase.tar
if [ ! -f "$tarball" ]; then
  if ! command -v debootstrap >/dev/null; then
    echo "fresh-debian: installing debootstrap"
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap
  fi
  mirror=$(mirror_of_host)
  [ -n "$mirror" ] || die "no '$suite' source found in /etc/apt/sources.list{,.d}"
  echo "fresh-debian: making a minimal $suite root (once; cached in $tarball)"
  mkdir -p "$cache"
  stage=$(mktemp -d "$cache/stage.XXXXXX")
  trap 'rm -rf "$stage"' EXIT
  t0=$SECONDS
  debootstrap --variant=minbase "$suite" "$stage" "$mirror" >"$cache/debootstrap.log" 2>&1 ||
    die "debootstrap failed; see $cache/debootstrap.log"
  tar -C "$stage" -cf "$tarball.tmp" . && mv "$tarball.tmp" "$tarball"
  rm -rf "$stage"; trap - EXIT
  echo "fresh-debian: root made in $((SECONDS - t0)) s"
fi

# --- a new root from the pristine copy ---------------------------------------------------
chroot_dir=$work/root
mounted=()
cleanup() {
  local m
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount -l "${mounted[$i]}" 2>/dev/null || true; done
  if [ "${SRICS_FRESH_KEEP:-0}" != 1 ]; then rm -rf "$chroot_dir"; fi
}
trap cleanup EXIT
for m in proc sys dev/pts dev; do umount -l "$chroot_dir/$m" 2>/dev/null || true; done
rm -rf "$chroot_dir"
mkdir -p "$chroot_dir"
tar -C "$chroot_dir" -xf "$tarball"

# the host's apt sources (all of them: updates and security too) and name resolution
rm -f "$chroot_dir"/etc/apt/sources.list
mkdir -p "$chroot_dir"/etc/apt/sources.list.d
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
  [ -f "$f" ] && cp "$f" "$chroot_dir$f"
done
cp -L /etc/resolv.conf "$chroot_dir/etc/resolv.conf" 2>/dev/null || true

mount -t proc proc "$chroot_dir/proc" && mounted+=("$chroot_dir/proc")
mount --rbind /sys "$chroot_dir/sys" && mounted+=("$chroot_dir/sys")
mount --rbind /dev "$chroot_dir/dev" && mounted+=("$chroot_dir/dev")

# the checkout as it is now: tracked and untracked files, without ignored ones (build/, runs/)
dest=$chroot_dir/srv/srics
mkdir -p "$dest"
(cd "$root" && git ls-files -z --cached --others --exclude-standard) |
  (cd "$root" && xargs -0 -r cp --parents -a -t "$dest" 2>/dev/null || true)
[ -f "$dest/tests/run.sh" ] || die "copying the checkout into the root failed"

echo "fresh-debian: running in a minimal $suite root: $command"
t0=$SECONDS
set +e
chroot "$chroot_dir" /usr/bin/env -i HOME=/root TERM="${TERM:-dumb}" \
  PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 \
  /bin/bash -c "cd /srv/srics && export SRICS_PHASE_TIMES=/srv/srics/phase-times.txt && $command"
rc=$?
set -e
total=$((SECONDS - t0))
mkdir -p "$work"
{
  echo "command: $command"
  echo "exit code: $rc"
  echo "total seconds: $total"
  if [ -f "$dest/phase-times.txt" ]; then cat "$dest/phase-times.txt"; fi
} | tee "$work/fresh-debian-times.txt"
exit $rc
