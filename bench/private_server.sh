# Sourced by the fleet benches: a private PostgreSQL server for the run (initdb and pg_ctl in a
# temporary folder, a Unix socket, no TCP port; as root it runs as the user postgres), stopped and
# removed at exit. Gives $work (the folder), $uri (the fleet's map, database "fleet"), psql (as
# the admin role), postmaster_cpu (its CPU seconds so far). Needs $memloop.
bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -1)
work=$(mktemp -d)
as=""
if [ "$(id -u)" -eq 0 ]; then as="runuser -u postgres --"; chown postgres "$work"; fi
stop() { $as "$bin/pg_ctl" -D "$work/data" -m immediate stop >/dev/null 2>&1 || true; rm -rf "$work"; }
trap stop EXIT
$as "$bin/initdb" --no-sync --auth=trust -U admin -D "$work/data" >/dev/null
$as "$bin/pg_ctl" -D "$work/data" -l "$work/log" -w -o "-k $work -c listen_addresses=''" start >/dev/null
psql() { command psql -h "$work" -U admin -qAt "$@"; }
psql -d postgres -c "CREATE DATABASE fleet"
uri="postgresql:///fleet?host=$work"
postmaster_cpu() { awk '{print ($14 + $15 + $16 + $17) / 100}' "/proc/$(head -1 "$work/data/postmaster.pid")/stat"; }
seconds_since() { printf %.1f "$(echo "$(date +%s.%N) - $1" | bc)"; }
