#!/usr/bin/env bash
# Debian roots for testing on another release than the machine's own (trixie with FreeCAD 1.0
# on a bookworm machine): made with debootstrap, entered with chroot. Sourced by
# tests/trixie/run.sh and tests/package/run.sh; runs as root.
#
#   root_bare CACHE SUITE        -> CACHE/SUITE-bare.tar (a minbase root, made once)
#   root_unpack TAR DIR          a fresh copy of a root in DIR (DIR is removed first)
#   root_enter DIR CMD...        runs CMD inside DIR with /proc, /sys, /dev mounted
#   root_remove DIR              removes DIR, never while anything is mounted below it
#
# Everything below a root is mounted by root_enter and unmounted when CMD ends, whatever
# its exit status; root_remove refuses a root with mounts left in it (removing a bind-mounted
# /dev would remove the machine's own device nodes).

DEBIAN_MIRROR="${DEBIAN_MIRROR:-http://deb.debian.org/debian}"

root_need_debootstrap() {
  if ! command -v debootstrap >/dev/null; then
    echo "debian-root: installing debootstrap"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    DEBIAN_FRONTEND=noninteractive $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
      debootstrap >/dev/null
  fi
}

root_bare() {
  local cache="$1" suite="$2"
  local tar="$cache/$suite-bare.tar"
  if [ -f "$tar" ]; then return 0; fi
  root_need_debootstrap
  local dir="$cache/$suite-debootstrap"
  root_remove "$dir"
  mkdir -p "$cache"
  echo "debian-root: debootstrap $suite (minbase) into $dir"
  debootstrap --variant=minbase --include=ca-certificates,git,make,sudo "$suite" "$dir" \
    "$DEBIAN_MIRROR" >"$cache/$suite-debootstrap.log" 2>&1 \
    || { tail -20 "$cache/$suite-debootstrap.log"; return 1; }
  tar -C "$dir" -cf "$tar.part" . && mv "$tar.part" "$tar"
  root_remove "$dir"
}

root_unpack() {
  local tar="$1" dir="$2"
  root_remove "$dir"
  mkdir -p "$dir"
  tar -C "$dir" -xf "$tar"
}

# Mount points below DIR, deepest first.
root_mounts() {
  local dir
  dir="$(realpath -m "$1")"
  awk -v d="$dir/" '{ gsub(/\\040/, " ", $2); if (index($2 "/", d) == 1) print $2 }' /proc/mounts \
    | sort -r
}

root_unmount() {
  local m
  for m in $(root_mounts "$1"); do
    umount "$m" 2>/dev/null || umount -l "$m"
  done
}

root_remove() {
  local dir="$1"
  [ -e "$dir" ] || return 0
  root_unmount "$dir"
  if [ -n "$(root_mounts "$dir")" ]; then
    echo "debian-root: refusing to remove $dir: still mounted: $(root_mounts "$dir" | tr '\n' ' ')" >&2
    return 1
  fi
  rm -rf --one-file-system "$dir"
}

root_enter() {
  local dir="$1"; shift
  dir="$(realpath "$dir")"
  mount -t proc proc "$dir/proc"
  mount -t sysfs sys "$dir/sys"
  mount --bind /dev "$dir/dev"
  mount --bind /dev/pts "$dir/dev/pts"
  mount -t tmpfs -o size=2g shm "$dir/dev/shm"
  cp -L /etc/resolv.conf "$dir/etc/resolv.conf" 2>/dev/null || true
  local rc=0
  chroot "$dir" /usr/bin/env -i HOME=/root TERM="${TERM:-dumb}" LANG=C.UTF-8 \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin "$@" || rc=$?
  root_unmount "$dir"
  return "$rc"
}
