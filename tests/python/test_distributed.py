"""Brick jobs on Dask distributed: the same mesh as one process for 1, 8 and 64
jobs, a killed worker costs a retry, a cancel leaves nothing, and `frepcad export --bricks`."""

import os
import signal
import subprocess
import zipfile

import pytest

import frepcore as fc
import frepcore.distributed as fd

SOURCE = os.environ.get("FREP_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
FREPCAD = os.environ.get("FREPCAD_BIN")


def sorted_triangles(path):
    """The mesh's triangles as coordinates, each turned to start at its smallest corner
    (orientation kept), sorted: equal for the same triangles in any order."""
    mesh = fc.read_mesh(path)
    points = mesh.points
    out = []
    for t in mesh.triangles:
        c = [tuple(points[i]) for i in t]
        k = c.index(min(c))
        out.append(tuple(c[k:] + c[:k]))
    out.sort()
    return out


@pytest.fixture(scope="module")
def client():
    from distributed import Client

    cluster = fd.local_cluster(2)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def model(name):
    return fc.load(os.path.join(SOURCE, "examples", name + ".json"))[0]


def test_one_eight_and_sixty_four_jobs_give_the_one_process_mesh(client, tmp_path):
    shape = model("csg")
    one = str(tmp_path / "one.stl")
    shape.export(one, cells=80)
    expected = sorted_triangles(one)
    assert len(expected) > 10000
    for bricks in (1, 8, 64):
        out = str(tmp_path / ("jobs%d.stl" % bricks))
        report = fd.export_distributed(shape, out, bricks, client=client, cells=80)
        assert report["printable"] and report["written"]
        assert report["checked_in_parts"]  # (a binary STL: the mesh never whole in memory)
        assert len(report["jobs"]) == bricks
        assert sorted_triangles(out) == expected, "%d jobs" % bricks
    # the pieces' folder is gone
    assert sorted(os.listdir(tmp_path)) == ["jobs1.stl", "jobs64.stl", "jobs8.stl", "one.stl"]


def test_flat_vertices_kept_or_not_in_jobs_give_the_one_process_mesh(client, tmp_path):
    shape = model("twist")
    meshes = {}
    for fewer in (True, False):
        one = str(tmp_path / "one.stl")
        shape.export(one, cells=80, drop_flat_vertices=fewer)
        meshes[fewer] = sorted_triangles(one)
        out = str(tmp_path / "jobs.stl")
        report = fd.export_distributed(shape, out, 8, client=client, cells=80,
                                       drop_flat_vertices=fewer)
        assert report["printable"] and report["written"]
        assert sorted_triangles(out) == meshes[fewer]
    assert len(meshes[True]) < 0.95 * len(meshes[False])


def test_a_killed_worker_costs_a_retry_not_a_wrong_brick(tmp_path):
    from distributed import Client

    cluster = fd.local_cluster(2)
    c = Client(cluster)
    shape = model("gyroid")
    killed = []

    def kill_a_busy_worker(stage, done, total):
        # after the first job, while others are in flight: SIGKILL a worker with work
        if stage == "bricks" and not killed and done < total:
            for address, keys in c.processing().items():
                if keys:
                    pid = c.run(os.getpid, workers=[address])[address]
                    os.kill(pid, signal.SIGKILL)
                    killed.append((pid, len(keys)))
                    break
        return True

    try:
        out = str(tmp_path / "gyroid.stl")
        report = fd.export_distributed(shape, out, 64, client=c, cells=96,
                                       progress=kill_a_busy_worker)
    finally:
        c.close()
        cluster.close()
    assert killed, "no worker was busy after the first job"
    assert report["printable"]
    assert all(j is not None for j in report["jobs"])
    one = str(tmp_path / "one.stl")
    shape.export(one, cells=96)
    assert sorted_triangles(out) == sorted_triangles(one)


def test_a_cancel_stops_the_jobs_and_leaves_nothing(client, tmp_path):
    out = str(tmp_path / "part.stl")
    with pytest.raises(fc.Cancelled):
        fd.export_distributed(model("gyroid"), out, 8, client=client, cells=96,
                              progress=lambda stage, done, total: done < 2)
    assert os.listdir(tmp_path) == []


def test_a_job_count_the_bricks_cannot_take_is_refused(client, tmp_path):
    with pytest.raises(ValueError, match="7 jobs cannot be cut"):
        fd.export_distributed(model("sphere"), str(tmp_path / "s.stl"), 7, client=client,
                              cells=40)
    assert os.listdir(tmp_path) == []


def test_frepcad_export_bricks(tmp_path):
    csg = os.path.join(SOURCE, "examples", "csg.json")
    out, one = str(tmp_path / "csg.stl"), str(tmp_path / "one.stl")
    run = subprocess.run([FREPCAD, "export", csg, "-o", out, "--bricks", "8", "--cells", "64"],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "as 8 brick jobs (2x2x2)" in run.stdout
    assert "verdict: printable" in run.stdout
    subprocess.run([FREPCAD, "export", csg, "-o", one, "--cells", "64", "--quiet"], check=True)
    assert sorted_triangles(out) == sorted_triangles(one)
    # a 3MF is streamed as the merge goes too, and holds the same floats
    package = str(tmp_path / "csg.3mf")
    run = subprocess.run([FREPCAD, "export", csg, "-o", package, "--bricks", "8", "--cells", "64",
                          "--units", "cm", "--quiet"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert zipfile.ZipFile(package).testzip() is None  # (every part's CRC: deflated in blocks)
    back = fc.read_3mf(package)
    assert back["unit"] == "cm" and back["metadata"]["Application"] == "FRepCAD frepcad export"
    assert [name for name, _ in back["objects"]] == ["csg"]
    assert sorted_triangles(package) == sorted_triangles(one)

    def refused(*args):
        r = subprocess.run([FREPCAD, "export", csg, "-o", str(tmp_path / "x.stl")] + list(args),
                           capture_output=True, text=True, timeout=300)
        assert r.returncode == 2, r.stdout + r.stderr
        assert not os.path.exists(tmp_path / "x.stl")
        return r.stderr

    assert "--scheduler and --work-dir apply to --bricks only" in refused("--scheduler", "x")
    assert "--bricks must be a whole number" in refused("--bricks", "0")
    assert "cannot be combined with --tolerance" in refused("--bricks", "8", "--tolerance", "0.01")
    assert "cannot be cut" in refused("--bricks", "7", "--cells", "32")
    # a scheduler that does not answer: an error naming it, no file
    r = subprocess.run([FREPCAD, "export", csg, "-o", str(tmp_path / "x.stl"), "--bricks", "2",
                        "--scheduler", "tcp://127.0.0.1:9"], capture_output=True, text=True,
                       timeout=300, env=dict(os.environ, DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT="2s"))
    assert r.returncode == 2 and "tcp://127.0.0.1:9" in r.stderr, r.stderr
    assert sorted(os.listdir(tmp_path)) == ["csg.3mf", "csg.stl", "one.stl"]
