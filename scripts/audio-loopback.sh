#!/usr/bin/env bash
# A software audio loopback for tests and for the lab without hardware.
#
# Starts PulseAudio as an ordinary per-user daemon (also as root: no --system, no D-Bus,
# no autospawn) with every runtime file under one private folder, loads a null sink
# `loop`, and makes `loop` the default sink and `loop.monitor` the default source. Whatever
# is played to the default output can then be recorded from the default input. PortAudio
# (and so sounddevice) reaches it through ALSA's pulse plugin (Debian libasound2-plugins),
# as the ALSA devices `pulse` and `default`.
#
# Usage:
#   bash scripts/audio-loopback.sh [start]   start, or check and repair a running loopback
#   bash scripts/audio-loopback.sh status    print the state; exit 1 when not running
#   bash scripts/audio-loopback.sh stop      stop the daemon and remove its folder
#
# `start` prints KEY=VALUE lines on stdout (messages go to stderr):
#   PULSE_SERVER=unix:<dir>/native   export it (and PULSE_RUNTIME_PATH) in the client
#   PULSE_RUNTIME_PATH=<dir>
#   PULSE_CLIENTCONFIG=<dir>/client.conf
#   PULSE_COOKIE=<dir>/home/pulse/cookie
#   DSTOOLKIT_LOOPBACK_STATE=started|running
#   DSTOOLKIT_LOOPBACK_SINK=loop
#   DSTOOLKIT_LOOPBACK_SOURCE=loop.monitor
# so that `export $(bash scripts/audio-loopback.sh)` points a shell (and the Python it starts)
# at the loopback.
#
# The folder is private and made by this script, never a predictable name in a shared /tmp:
#   - $DSTOOLKIT_PULSE_DIR or $PULSE_RUNTIME_PATH when set (as printed by an earlier `start`):
#     it must be a real folder (not a symlink) owned by this user with mode 0700, or not
#     exist yet (then it is created with mode 0700);
#   - else $XDG_RUNTIME_DIR/dstoolkit-pulse, when $XDG_RUNTIME_DIR is a real folder owned by
#     this user with mode 0700 (dstoolkit-pulse is created with mode 0700, or checked so);
#   - else a new folder from `mktemp -d` (mode 0700). `start` is then idempotent, and
#     `status`/`stop` work, only with the PULSE_RUNTIME_PATH that `start` printed in the
#     environment.
# No file is written through a symlink: the folders are checked, and each file is removed
# (rm -f does not follow a symlink) and created anew with noclobber.
# Needs: apt-get install pulseaudio pulseaudio-utils libasound2-plugins libportaudio2
set -euo pipefail

say() { echo "audio-loopback: $*" >&2; }

# private DIR: true when DIR is a real folder (not a symlink) of this user with mode 0700.
private() {
  [ -d "$1" ] && [ ! -L "$1" ] && [ "$(stat -c %u -- "$1")" = "$(id -u)" ] \
    && [ "$(stat -c %a -- "$1")" = 700 ]
}

# ensure_private DIR: create DIR with mode 0700, or check that it is private.
ensure_private() {
  if [ ! -e "$1" ] && [ ! -L "$1" ]; then
    mkdir -m 700 -- "$1" || { say "cannot create $1"; exit 4; }
  fi
  private "$1" || { say "refusing $1: not a folder of $(id -un) with mode 0700 (or a" \
    "symlink); remove it or choose another folder"; exit 4; }
}

# pick_dir [create]: set $dir (see the header); `create` makes it when missing.
pick_dir() {
  local given="${DSTOOLKIT_PULSE_DIR:-${PULSE_RUNTIME_PATH:-}}"
  if [ -n "$given" ]; then
    dir="$given"
  elif [ -n "${XDG_RUNTIME_DIR:-}" ] && private "$XDG_RUNTIME_DIR"; then
    dir="$XDG_RUNTIME_DIR/dstoolkit-pulse"
  elif [ "${1:-}" = create ]; then
    dir="$(mktemp -d "${TMPDIR:-/tmp}/dstoolkit-pulse.XXXXXXXX")"
  else
    say "which loopback? set PULSE_RUNTIME_PATH to the folder that \`start\` printed"
    exit 1
  fi
  if [ "${1:-}" = create ]; then
    ensure_private "$dir"
  elif [ -e "$dir" ] || [ -L "$dir" ]; then
    private "$dir" || { say "refusing $dir: not a folder of $(id -un) with mode 0700"; exit 4; }
  fi
  sink=loop
  rate="${DSTOOLKIT_LOOPBACK_RATE:-44100}"
  export PULSE_RUNTIME_PATH="$dir"
  export PULSE_SERVER="unix:$dir/native"
  # A client config that never autospawns a daemon of its own (libpulse's default would)
  # and keeps the client's cookie under $dir too (else libpulse writes
  # ~/.config/pulse/cookie).
  export PULSE_CLIENTCONFIG="$dir/client.conf"
  export PULSE_COOKIE="$dir/home/pulse/cookie"
}

# write_file PATH < text: PATH anew inside the private folder, never through a symlink.
write_file() {
  rm -f -- "$1"
  ( set -o noclobber; cat > "$1" )
}

need() {
  local missing=()
  command -v pulseaudio >/dev/null || missing+=(pulseaudio)
  command -v pactl >/dev/null || missing+=(pulseaudio-utils)
  if [ "${#missing[@]}" -gt 0 ]; then
    say "missing ${missing[*]}: apt-get install pulseaudio pulseaudio-utils" \
      "libasound2-plugins libportaudio2"
    exit 3
  fi
  # ALSA's pulse plugin, through which PortAudio reaches the daemon.
  if ! ls /usr/lib/*/alsa-lib/libasound_module_pcm_pulse.so >/dev/null 2>&1; then
    say "ALSA's pulse plugin is missing: apt-get install libasound2-plugins"
    exit 3
  fi
}

running() { pactl info >/dev/null 2>&1; }

print_state() {
  echo "PULSE_SERVER=$PULSE_SERVER"
  echo "PULSE_RUNTIME_PATH=$PULSE_RUNTIME_PATH"
  echo "PULSE_CLIENTCONFIG=$PULSE_CLIENTCONFIG"
  echo "PULSE_COOKIE=$PULSE_COOKIE"
  echo "DSTOOLKIT_LOOPBACK_STATE=$1"
  echo "DSTOOLKIT_LOOPBACK_SINK=$(pactl get-default-sink)"
  echo "DSTOOLKIT_LOOPBACK_SOURCE=$(pactl get-default-source)"
}

start() {
  need
  local state=running
  if ! running; then
    state=started
    ensure_private "$dir/home"
    ensure_private "$dir/home/pulse"
    ensure_private "$dir/state"
    printf 'autospawn = no\ndefault-server = %s\ncookie-file = %s\n' \
      "$PULSE_SERVER" "$PULSE_COOKIE" | write_file "$PULSE_CLIENTCONFIG"
    rm -f -- "$dir/native" "$dir/pid" "$dir/pulseaudio.log"
    # -n: no default.pa (it would probe sound cards, D-Bus, X11); the modules we need are
    # loaded explicitly. HOME/XDG_* keep the cookie and state out of the real home folder.
    # auth-anonymous=1: clients need no cookie (the socket sits in a 0700 folder).
    HOME="$dir/home" XDG_CONFIG_HOME="$dir/home" XDG_RUNTIME_DIR="$dir" \
      PULSE_STATE_PATH="$dir/state" \
      pulseaudio -n --daemonize=yes --use-pid-file=yes --system=no \
        --exit-idle-time=-1 --disallow-exit=no --realtime=no --high-priority=no \
        --log-target="file:$dir/pulseaudio.log" \
        -L "module-native-protocol-unix socket=$dir/native auth-anonymous=1" \
        -L "module-null-sink sink_name=$sink rate=$rate format=float32le" \
        || { say "pulseaudio failed to start; see $dir/pulseaudio.log:";
             cat "$dir/pulseaudio.log" >&2 || true; exit 1; }
    for _ in $(seq 50); do running && break; sleep 0.1; done
    running || { say "pulseaudio started but does not answer at $PULSE_SERVER"; exit 1; }
    # A sound server is a real-time job: put every thread of it ahead of CPU-bound work
    # where the system allows it (as root, or with a raised RLIMIT_NICE); elsewhere it
    # keeps the ordinary priority. On a busy machine this keeps the null sink's clock fed.
    for task in /proc/"$(cat "$dir/pid")"/task/*; do
      renice -n -10 -p "${task##*/}" >/dev/null 2>&1 || true
    done
  fi
  # Repair a running daemon that lost its sink or its defaults (idempotent).
  if ! pactl list short sinks | cut -f2 | grep -qx "$sink"; then
    pactl load-module module-null-sink "sink_name=$sink" "rate=$rate" format=float32le \
      >/dev/null
  fi
  pactl set-default-sink "$sink"
  pactl set-default-source "$sink.monitor"
  say "$state: sink $sink, source $sink.monitor, server $PULSE_SERVER"
  print_state "$state"
}

stop() {
  if [ -f "$dir/pid" ] && running; then
    pulseaudio --kill 2>/dev/null || pactl exit 2>/dev/null || true
    for _ in $(seq 50); do running || break; sleep 0.1; done
    say "stopped"
  else
    say "not running"
  fi
  # Remove only what start created, then the folder if it is empty.
  rm -rf -- "$dir/home" "$dir/state"
  rm -f -- "$dir/native" "$dir/pid" "$dir/client.conf" "$dir/pulseaudio.log"
  rmdir -- "$dir" 2>/dev/null || true
}

case "${1:-start}" in
  start) pick_dir create; start ;;
  stop) pick_dir; stop ;;
  status)
    pick_dir
    if running; then print_state running; else say "not running ($PULSE_SERVER)"; exit 1; fi ;;
  *) echo "usage: $0 [start|status|stop]" >&2; exit 2 ;;
esac
