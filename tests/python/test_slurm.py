"""workflow/Snakefile on a real SLURM scheduler: a single-node cluster started here (munge,
slurmctld, slurmd from Debian 12's slurm-wlm, with a slurm.conf written for this machine),
the workflow run through Snakemake's SLURM executor with the profile docs/workflow.md
gives, each scan a SLURM job; the meshes equal a local run's byte for byte and the reports
field for field (times and memory aside), and a scan that fails leaves the others done and
the index showing its error. The daemons need root: without it the test fails with the
reason. Everything started is stopped at the end.

Run by ctest (tests/CMakeLists.txt) with MPUMESH_SOURCE_DIR and MPUMESH_BIN."""
import json
import os
import pwd
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from pathlib import Path

import pytest

from scan_phantoms import ball_scan

SOURCE = Path(os.environ["MPUMESH_SOURCE_DIR"])
BIN = os.environ["MPUMESH_BIN"]
# The profile docs/workflow.md gives, with this cluster's partition, no account (the
# cluster keeps none), and jobs of one thread and 1 GB to fit any test machine.
PROFILE = """slurm: true
jobs: 4
keep-going: true
max-status-checks-per-second: 1
default-resources:
  - slurm_partition=debug
set-resources:
  - mesh:mem_mb=1000
  - mesh:runtime=20
set-threads:
  - mesh=1
"""


def slurm_conf(d, node_line):
    return f"""ClusterName=mpumesh-test
SlurmctldHost={socket.gethostname().split('.')[0]}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={d}/munge/munge.socket
CredType=cred/munge
ProctrackType=proctrack/pgid
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmctldPort=16817
SlurmdPort=16818
StateSaveLocation={d}/state
SlurmdSpoolDir={d}/spool
SlurmctldPidFile={d}/slurmctld.pid
SlurmdPidFile={d}/slurmd.pid
SlurmctldLogFile={d}/slurmctld.log
SlurmdLogFile={d}/slurmd.log
ReturnToService=2
MpiDefault=none
{node_line} State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
"""


class Cluster:
    """A single-node SLURM cluster in folder `d`, its clients' environment in `env`."""

    def __init__(self, d):
        self.d = d
        self.pids = []

    def start(self):
        if os.geteuid() != 0:
            pytest.fail("the SLURM test starts munged, slurmctld and slurmd, which needs root (CI runs as root)")
        for tool in ("munged", "slurmctld", "slurmd", "sbatch", "scontrol"):
            if not shutil.which(tool):
                pytest.fail(f"{tool} is missing: scripts/setup.sh installs slurm-wlm and munge")
        d = self.d
        for sub in ("state", "spool", "munge"):
            (d / sub).mkdir(parents=True)
        shutil.chown(d / "munge", "munge", "munge")
        (d / "munge").chmod(0o755)  # munged needs its socket's folder open to all
        munged = subprocess.run(["runuser", "-u", "munge", "--", "munged", f"--socket={d}/munge/munge.socket",
                                 f"--pid-file={d}/munge/munged.pid", f"--log-file={d}/munge/munged.log",
                                 f"--seed-file={d}/munge/seed"], capture_output=True, text=True)
        if munged.returncode != 0:
            pytest.fail(f"munged did not start: {munged.stderr.strip()}")
        self.pid_files = [d / "munge" / "munged.pid"]
        node = subprocess.run(["slurmd", "-C"], capture_output=True, text=True, check=True).stdout.splitlines()[0]
        (d / "slurm.conf").write_text(slurm_conf(d, node))
        self.env = dict(os.environ, SLURM_CONF=str(d / "slurm.conf"), USER=pwd.getpwuid(os.geteuid()).pw_name)
        self.env.pop("PYTHONPATH", None)
        subprocess.run(["slurmctld", "-c"], env=self.env, check=True)
        self.pid_files.append(d / "slurmctld.pid")
        subprocess.run(["slurmd"], env=self.env, check=True)
        self.pid_files.append(d / "slurmd.pid")
        for _ in range(60):  # the node registers and turns idle
            state = subprocess.run(["sinfo", "-h", "-o", "%T"], env=self.env, capture_output=True, text=True)
            if state.stdout.strip() == "idle":
                return
            time.sleep(0.5)
        logs = "".join((d / f).read_text()[-2000:] for f in ("slurmctld.log", "slurmd.log") if (d / f).exists())
        pytest.fail(f"the SLURM node did not become idle: {state.stdout} {state.stderr}\n{logs}")

    def stop(self):
        for pid_file in reversed(getattr(self, "pid_files", [])):
            try:
                os.kill(int(pid_file.read_text().split()[0]), signal.SIGTERM)
            except (OSError, ValueError):
                pass
        time.sleep(1)

    def jobs(self):
        """Every job the controller knows: (name, state, id)."""
        out = subprocess.run(["scontrol", "show", "job", "-o"], env=self.env, capture_output=True, text=True).stdout
        rows = []
        for line in out.splitlines():
            fields = dict(f.split("=", 1) for f in line.split() if "=" in f)
            rows.append((fields.get("JobName"), fields.get("JobState"), fields.get("JobId")))
        return rows


@pytest.fixture(scope="module")
def cluster():
    # munged needs every folder above its socket open to all, which pytest's are not.
    d = Path(tempfile.mkdtemp(prefix="mpumesh-slurm-"))
    d.chmod(0o755)
    c = Cluster(d)
    try:
        c.start()
        yield c
    finally:
        c.stop()
        shutil.rmtree(d, ignore_errors=True)


def snakemake(workdir, scans, out, extra, env=None):
    return subprocess.run(
        ["snakemake", "-s", str(SOURCE / "workflow" / "Snakefile"), *extra, "--directory", str(workdir), "--config",
         f"input_dir={scans}", f"output_dir={out}", f"mpumesh={BIN}", "threads=1",
         "run_options=--particles 1500 --backend cpu"],
        capture_output=True, text=True, env=env)


def comparable(report, out):
    """A report without its times and memory, its paths relative to the output folder."""
    if isinstance(report, dict):
        return {k: comparable(v, out) for k, v in report.items()
                if "seconds" not in k and not k.endswith("_ms") and k != "memory"}
    if isinstance(report, list):
        return [comparable(v, out) for v in report]
    if isinstance(report, str) and report.startswith(str(out)):
        return os.path.relpath(report, out)
    return report


def test_the_workflow_on_slurm_equals_the_local_run(cluster, tmp_path):
    scans = tmp_path / "scans"
    scans.mkdir()
    for name, radius in (("small", 5.0), ("middle", 6.0), ("large", 7.0)):
        ball_scan(scans / f"{name}.nii.gz", radius)
    (scans / "broken.nii.gz").write_bytes(b"this is no NIfTI file")
    profile = tmp_path / "profile"
    profile.mkdir()
    (profile / "config.yaml").write_text(PROFILE)

    local = snakemake(tmp_path / "local", scans, tmp_path / "local" / "meshes", ["--cores", "2", "--keep-going"])
    started = time.monotonic()
    slurm = snakemake(tmp_path / "slurm", scans, tmp_path / "slurm" / "meshes", ["--profile", str(profile)],
                      env=cluster.env)
    seconds = time.monotonic() - started
    print(f"workflow under SLURM: {seconds:.1f} s")
    # The broken scan fails in both, the others finish.
    assert local.returncode != 0 and slurm.returncode != 0, slurm.stdout + slurm.stderr
    assert "broken" in slurm.stdout + slurm.stderr

    # Each scan ran as a SLURM job, under its id: the controller's record and the job's log.
    jobs = [j for j in cluster.jobs() if j[0] and "mesh" in j[0]]
    assert len(jobs) == 4, cluster.jobs()
    assert sorted(state for _, state, _ in jobs) == ["COMPLETED", "COMPLETED", "COMPLETED", "FAILED"], jobs
    logs = list((tmp_path / "slurm" / ".snakemake" / "slurm_logs" / "rule_mesh").glob("*.log"))
    assert sorted(p.stem for p in logs) == sorted(job_id for _, _, job_id in jobs)

    a, b = tmp_path / "local" / "meshes", tmp_path / "slurm" / "meshes"
    for name in ("small", "middle", "large"):
        assert (a / f"{name}.ply").read_bytes() == (b / f"{name}.ply").read_bytes(), name
        ra, rb = (json.loads((d / f"{name}.json").read_text()) for d in (a, b))
        assert comparable(ra, a) == comparable(rb, b), name
    assert not (b / "broken.ply").exists()
    assert "mpumesh: error:" in (b / "logs" / "broken.log").read_text()
    index = (b / "index.html").read_text()
    assert "failed: mpumesh: error:" in index and "broken" in index
    for name in ("small", "middle", "large"):
        assert index.count(f"{name}.ply") == 1
