#!/usr/bin/env bash
# ci/slurm-local.sh start|stop|status
#
# A throwaway single-node SLURM cluster on this Debian machine, for CI and for trying the
# `profiles/slurm` profile: Debian's slurmctld + slurmd + munge, started directly (no systemd),
# no accounting database (so job status comes from `squeue`; MinJobAge is raised so finished jobs
# stay visible there). Must run as root on Debian.
#
#   start   install the packages if missing (apt-get, non-interactive), create the munge key if
#           absent, write slurm.conf, start munged (as user munge), slurmctld and slurmd, and wait
#           until `sinfo` shows the node idle. Idempotent: a running cluster is left as is.
#   stop    kill the daemons by their PID files, remove PID files and runtime state.
#   status  print daemon PIDs and `sinfo`; exit 0 if the cluster is up, 1 otherwise.
#
# Environment: SLURM_LOCAL_PARTITION (default "debug"), SLURM_LOCAL_TIMEOUT (seconds to wait for
# the node, default 60), SLURM_LOCAL_DIR (state, logs, PID files; default /var/lib/slurm-local).
set -euo pipefail

PARTITION=${SLURM_LOCAL_PARTITION:-debug}
TIMEOUT=${SLURM_LOCAL_TIMEOUT:-60}
BASE=${SLURM_LOCAL_DIR:-/var/lib/slurm-local}
CONF_DIR=/etc/slurm
CONF=$CONF_DIR/slurm.conf
MARKER="# written by bearing_envelope ci/slurm-local.sh"
CTLD_PID=$BASE/slurmctld.pid
SLURMD_PID=$BASE/slurmd.pid
MUNGE_PID=/run/munge/munged.pid
MUNGE_OURS=$BASE/munged.started-by-us

die() { echo "slurm-local: ERROR: $*" >&2; exit 1; }
log() { echo "slurm-local: $*" >&2; }

preflight() {
    [[ $(id -u) -eq 0 ]] || die "must run as root (it installs Debian packages and starts daemons); you are $(id -un)"
    [[ -r /etc/debian_version ]] || die "this script supports Debian only (/etc/debian_version not found)"
    command -v apt-get >/dev/null || die "apt-get not found; Debian required"
}

pid_alive() { [[ -s $1 ]] && kill -0 "$(cat "$1")" 2>/dev/null; }

install_packages() {
    local missing=()
    for p in slurmctld slurmd slurm-client munge; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [[ ${#missing[@]} -eq 0 ]] && return 0
    log "installing ${missing[*]} (apt-get)"
    export DEBIAN_FRONTEND=noninteractive
    # Keep maintainer scripts from starting services (no systemd here; we start daemons ourselves).
    local prc=/usr/sbin/policy-rc.d created_prc=0
    if [[ ! -e $prc ]]; then
        printf '#!/bin/sh\nexit 101\n' >"$prc"; chmod +x "$prc"; created_prc=1
    fi
    { apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null; } \
        || { [[ $created_prc -eq 1 ]] && rm -f "$prc"; die "apt-get install ${missing[*]} failed"; }
    [[ $created_prc -eq 1 ]] && rm -f "$prc"
    return 0
}

setup_munge() {
    install -d -m 0755 "$BASE"
    install -d -o munge -g munge -m 0700 /etc/munge /var/lib/munge /var/log/munge
    install -d -o munge -g munge -m 0755 /run/munge
    if [[ ! -s /etc/munge/munge.key ]]; then
        log "creating munge key"
        if command -v mungekey >/dev/null; then
            mungekey --create --keyfile=/etc/munge/munge.key --force
        else
            dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
        fi
    fi
    chown munge:munge /etc/munge/munge.key; chmod 0400 /etc/munge/munge.key
    if pid_alive "$MUNGE_PID" && munge -n </dev/null | unmunge >/dev/null 2>&1; then
        return 0
    fi
    log "starting munged as user munge"
    rm -f "$MUNGE_PID" /run/munge/munge.socket.2*
    # munged refuses to run as root; runuser keeps it under the munge account.
    runuser -u munge -- /usr/sbin/munged --pid-file="$MUNGE_PID" \
        || die "munged failed to start (see /var/log/munge/munged.log)"
    touch "$MUNGE_OURS"
    for _ in $(seq 50); do munge -n </dev/null | unmunge >/dev/null 2>&1 && return 0; sleep 0.1; done
    die "munge does not answer (see /var/log/munge/munged.log)"
}

write_conf() {
    local host node_line
    host=$(hostname -s)
    # The node's real hardware, as slurmd sees it ("NodeName=... CPUs=... RealMemory=...").
    node_line=$(slurmd -C | grep '^NodeName=') || die "slurmd -C failed"
    node_line=$(sed -E "s/^NodeName=[^ ]+/NodeName=$host/; s/ *UpTime=.*//" <<<"$node_line")
    if [[ -e $CONF ]] && ! grep -qF "$MARKER" "$CONF"; then
        die "$CONF exists and was not written by this script; refusing to overwrite it (move it away first)"
    fi
    install -d -m 0755 "$CONF_DIR" "$BASE" "$BASE/ctld" "$BASE/d" "$BASE/log"
    cat >"$CONF.tmp" <<EOF
$MARKER -- regenerated on every start; edits are lost.
ClusterName=bearingenv
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CryptoType=crypto/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
SchedulerType=sched/backfill
# schedule at once on submit/completion (defaults delay batch jobs up to 3 s)
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
DefMemPerCPU=1024
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
# finished jobs stay visible to squeue/scontrol for an hour (no accounting DB here)
MinJobAge=3600
ReturnToService=2
StateSaveLocation=$BASE/ctld
SlurmdSpoolDir=$BASE/d
SlurmctldPidFile=$CTLD_PID
SlurmdPidFile=$SLURMD_PID
SlurmctldLogFile=$BASE/log/slurmctld.log
SlurmdLogFile=$BASE/log/slurmd.log
SlurmctldTimeout=30
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
Waittime=0
$node_line State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
EOF
    mv "$CONF.tmp" "$CONF"
    # cgroup.conf is not needed with proctrack/linuxproc + task/none.
}

node_state() { sinfo -h -N -o '%t' 2>/dev/null | head -1; }

do_start() {
    preflight
    local t0=$SECONDS
    install_packages
    setup_munge
    if pid_alive "$CTLD_PID" && pid_alive "$SLURMD_PID" && [[ $(node_state) == idle* || $(node_state) == mix* || $(node_state) == alloc* ]]; then
        log "already running: $(sinfo -h -N -o '%N %t %c CPUs %m MB')"
        return 0
    fi
    write_conf
    if ! pid_alive "$CTLD_PID"; then
        log "starting slurmctld"
        # -i: ignore state files that do not match this config (a stale state from an older start).
        /usr/sbin/slurmctld -i || die "slurmctld failed to start (see $BASE/log/slurmctld.log)"
    fi
    if ! pid_alive "$SLURMD_PID"; then
        log "starting slurmd"
        /usr/sbin/slurmd || die "slurmd failed to start (see $BASE/log/slurmd.log)"
    fi
    local st=""
    for _ in $(seq $((TIMEOUT * 2))); do
        st=$(node_state)
        case $st in
            idle*|mix*|alloc*) break ;;
            down*|drain*|drng*|fail*)
                # a node registered after a previous run: bring it back
                scontrol update NodeName="$(hostname -s)" State=RESUME >/dev/null 2>&1 || true ;;
        esac
        sleep 0.5
    done
    case $st in
        idle*|mix*|alloc*) ;;
        *) sinfo -N -l >&2 || true
           tail -n 20 "$BASE/log/slurmctld.log" "$BASE/log/slurmd.log" >&2 || true
           die "node not idle after ${TIMEOUT}s (state '${st:-none}')" ;;
    esac
    log "up in $((SECONDS - t0))s: $(sinfo -h -N -o '%N partition=%P state=%t cpus=%c mem=%mMB')"
}

kill_pidfile() {  # name pidfile
    local name=$1 f=$2 pid
    [[ -s $f ]] || return 0
    pid=$(cat "$f")
    if kill -0 "$pid" 2>/dev/null; then
        log "stopping $name (pid $pid)"
        kill -TERM "$pid" 2>/dev/null || true
        for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        if kill -0 "$pid" 2>/dev/null; then log "$name did not exit; SIGKILL"; kill -KILL "$pid" 2>/dev/null || true; fi
    fi
    rm -f "$f"
}

do_stop() {
    preflight
    # Cancel what is still queued or running, so slurmd leaves no job steps behind.
    if pid_alive "$CTLD_PID"; then scancel --full --quiet "--partition=$PARTITION" 2>/dev/null || true; sleep 1; fi
    kill_pidfile slurmd "$SLURMD_PID"
    kill_pidfile slurmctld "$CTLD_PID"
    if [[ -e $MUNGE_OURS ]]; then
        kill_pidfile munged "$MUNGE_PID"
        rm -f "$MUNGE_OURS"
    fi
    # runtime state only; the packages, munge key and logs stay for the next start / post-mortem.
    rm -rf "$BASE/ctld" "$BASE/d"
    log "stopped"
}

do_status() {
    local up=0
    for x in "munged:$MUNGE_PID" "slurmctld:$CTLD_PID" "slurmd:$SLURMD_PID"; do
        if pid_alive "${x#*:}"; then echo "${x%%:*}: running (pid $(cat "${x#*:}"))"
        else echo "${x%%:*}: not running"; up=1; fi
    done
    if [[ $up -eq 0 ]]; then sinfo -N -o '%N %P %t %c %m' || up=1; fi
    return $up
}

case ${1:-} in
    start) do_start ;;
    stop) do_stop ;;
    status) do_status ;;
    *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
