"""Exports beyond one process: brick jobs scheduled by Dask distributed.

The export is cut into jobs, each a box of the mesher's bricks (libcore's
pipeline/brick_jobs.h). A Dask worker meshes a job into a piece file in a shared work folder.
This process then welds the pieces by key, checks the mesh and writes it atomically. The
mesh is the one a one-process export writes: the same triangles, the same coordinates.

    import frepcore, frepcore.distributed as fd
    shape, _ = frepcore.load("examples/gyroid.json")
    fd.export_distributed(shape, "gyroid.stl", bricks=8, cells=512)             # LocalCluster
    fd.export_distributed(shape, "gyroid.stl", bricks=64, cells=1024,
                          scheduler="tcp://host:8786", work_dir="/shared/tmp")  # a cluster

`frepcad export MODEL -o OUT --bricks N [--scheduler ADDRESS]` comes here
(`python3 -m frepcore.distributed`, its options in FREPCAD_EXPORT_ARGS).

Dask is imported only when a run starts, so frepcore itself does not need it.
"""

import json
import os
import shutil
import signal
import sys
import tempfile
import time

import frepcore

# A job is tried again this many times when it raises; a job whose worker dies is given to
# another worker by the scheduler (up to distributed's allowed-failures, 3 by default).
RETRIES = 3


_policy_set = False


def mesh_job(model_text, base_dir, bbox, resolution, jobs, job, path, threads=0,
             settings=None):
    """On a worker: meshes job `job` of the run into the piece file `path` on `threads`
    threads (0: every core) with `settings` (MeshSettings.to_dict()); returns the job's figures (triangles, seconds, the worker's
    peak memory in MB)."""
    global _policy_set
    if not _policy_set:
        # A worker process runs brick jobs one after another: the heap the first job grew is
        # reused by the next, without the page faults of fresh memory (base/process_memory.h).
        frepcore.use_one_job_memory_policy()
        _policy_set = True
    frepcore.set_threads(threads)
    model = frepcore.parse_model(model_text, "model", base_dir)
    result = model["root"].brick_job(bbox, resolution, jobs, job, path,
                                     frepcore.MeshSettings(**(settings or {})))
    result["peak_mb"] = peak_memory_mb()
    result["pid"] = os.getpid()
    return result


def peak_memory_mb():
    """This process's resident peak (VmHWM; getrusage's ru_maxrss would count a forking
    parent's peak too: Linux keeps it across exec), in MB, or None where unknown."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def local_cluster(workers=None):
    """A LocalCluster of `workers` one-thread worker processes (default: the machine's
    cores), quiet, without a dashboard."""
    import logging

    from distributed import LocalCluster

    return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                        processes=True, dashboard_address=":0", silence_logs=logging.ERROR)


def export_distributed(shape, path, bricks, scheduler=None, client=None, resolution=None,
                       bbox=None, cells=None, format="", check=True, force=False,
                       work_dir=None, progress=None, workers=None, base_dir=None,
                       threads_per_job=None, unit="", metadata=None, settings=None, **options):
    """Meshes `shape` as `bricks` jobs on Dask, welds, checks and writes `path` atomically.

    scheduler: a Dask scheduler's address; client: a distributed.Client to use as is;
    neither: a LocalCluster with `workers` processes (default: the machine's cores).
    work_dir: a folder every worker and this process can reach, for the piece files (default:
    a temporary folder beside `path`; removed at the end either way).
    progress(stage, done, total) -> False cancels: stage 'bricks' counts jobs done,
    'merge' goes from 0 to 1 over the merge, check and write.
    base_dir: where relative file names in the model (mesh_sdf, vdb_grid) are found.
    threads_per_job: the threads a job meshes on (0: every core of its worker's machine);
    default: the machine's cores shared out among a LocalCluster's workers, else 0.
    settings, options: the meshing options, as Shape.export takes them (mesher,
    sharp_features and drop_flat_vertices apply; a job cannot take a refinement, straightened
    creases or a tolerance: ValueError).
    unit, metadata: a 3MF's length unit ("micron", "mm", "cm", "inch", "ft", "m") and
    (name, value) pairs. A binary STL or a 3MF is written as the merge goes; other formats
    are merged in memory.

    Returns the export's report dict (as Shape.export) plus 'jobs' (each job's figures) and
    'split'. Raises NotPrintable (nothing written) when the check refuses and force is not
    given, Cancelled on a cancel (nothing written), ValueError for a job count the grid's
    bricks cannot take.
    """
    node = frepcore._node(shape)
    box, cell = frepcore.automatic_box(node, resolution=resolution, bbox=bbox, cells=cells)
    chosen = frepcore.mesh_settings(settings, **options)
    plan = node.brick_plan(box, cell, bricks, chosen)
    model_text = node.to_json()
    base_dir = os.path.abspath(base_dir or os.getcwd())
    out_dir = os.path.dirname(os.path.abspath(path))
    folder = tempfile.mkdtemp(prefix=".%s.bricks-" % os.path.basename(path),
                              dir=work_dir or out_dir)
    own_cluster = own_client = None
    futures = []
    try:
        if client is None:
            from distributed import Client

            if scheduler:
                client = own_client = Client(scheduler)
            else:
                own_cluster = local_cluster(workers)
                client = own_client = Client(own_cluster)
                if threads_per_job is None:
                    cores = os.cpu_count() or 1
                    threads_per_job = max(1, cores // len(own_cluster.workers))
        pieces = [os.path.join(folder, "job-%05d.piece" % j) for j in range(bricks)]
        run = "%016x" % plan["run_id"]
        futures = [client.submit(mesh_job, model_text, base_dir, box, cell, bricks, j,
                                 pieces[j], threads_per_job or 0, chosen.to_dict(),
                                 key="frepcad-%s-%d" % (run, j),
                                 retries=RETRIES, pure=False)
                   for j in range(bricks)]
        jobs = _gather(client, futures, progress)
        if progress is not None and progress("merge", 0.0, 1.0) is False:
            raise frepcore.Cancelled("cancelled")
        merge_progress = None
        if progress is not None:
            def merge_progress(f):
                return progress("merge", f, 1.0) is not False
        report = node.merge_bricks(box, cell, bricks, pieces, path,
                                   format=format, check=check, force=force,
                                   progress=merge_progress, unit=unit,
                                   metadata=[tuple(m) for m in (metadata or [])],
                                   settings=chosen)
        report["jobs"] = jobs
        report["split"] = plan["split"]
    finally:
        if futures and client is not None:
            client.cancel(futures)
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()
        _remove_folder(folder)
    if check and not report["printable"] and not force:
        raise frepcore.NotPrintable("%s: not written, the mesh is not printable: %s"
                                    % (path, "; ".join(report["reasons"])), report)
    return report


def _remove_folder(folder):
    """Removes the pieces' folder. A cancelled job still running may write into it while it
    goes (Dask does not stop a running task), so this tries again until the folder is gone;
    a job that finishes later cannot write (the folder is not made again)."""
    for _ in range(100):
        shutil.rmtree(folder, ignore_errors=True)
        if not os.path.exists(folder):
            return
        time.sleep(0.1)


def _gather(client, futures, progress):
    """Waits for every job, in the order they finish; returns their figures by job."""
    from distributed import as_completed

    jobs = [None] * len(futures)
    done = 0
    for future, result in as_completed(futures, with_results=True):
        jobs[result["job"]] = result
        done += 1
        if progress is not None and progress("bricks", done, len(futures)) is False:
            raise frepcore.Cancelled("cancelled")
    return jobs


def _terminal_progress(quiet):
    """A progress line on stderr (a terminal only), as frepcad's own bar."""
    if quiet or not sys.stderr.isatty():
        return None
    start = time.time()

    def show(stage, done, total):
        text = ("bricks %d/%d" % (done, total) if stage == "bricks"
                else "merge, check, write %3.0f%%" % (100.0 * done / total))
        sys.stderr.write("\r%-40s %6.1f s" % (text, time.time() - start))
        sys.stderr.flush()
        return True
    return show


def main():
    """`frepcad export MODEL -o OUT --bricks N`: the options come parsed by frepcad, with
    the box it chose, in FREPCAD_EXPORT_ARGS. Exit status as frepcad's: 0 written, 1 not
    printable, 130 cancelled, 2 for an error (printed as one line)."""
    args = json.loads(os.environ["FREPCAD_EXPORT_ARGS"])
    # a SIGTERM (frepcad passes on Ctrl-C so) cancels like Ctrl-C: jobs stopped, nothing left
    signal.signal(signal.SIGTERM, signal.default_int_handler)
    # this process runs one export and exits, as frepcad does: its memory policy
    frepcore.use_one_job_memory_policy()
    quiet = args.get("quiet", False)
    show = None
    try:
        shape, _ = frepcore.load(args["model"])
        show = _terminal_progress(quiet)
        report = export_distributed(
            shape, args["output"], args["bricks"], scheduler=args.get("scheduler"),
            resolution=args["resolution"], bbox=args["bbox"],
            settings=frepcore.MeshSettings(**args.get("settings", {})),
            format=args.get("format", ""),
            force=args.get("force", False), work_dir=args.get("work_dir"), progress=show,
            workers=args.get("workers"), unit=args.get("units", ""),
            metadata=args.get("metadata"),
            base_dir=os.path.dirname(os.path.abspath(args["model"])))
    except frepcore.NotPrintable as e:
        if show:
            sys.stderr.write("\n")
        print(e.report["text"], end="")
        sys.stderr.write("frepcad: refusing to write %s: the mesh is not printable (see "
                         "reasons above; --force writes it anyway)\n" % args["output"])
        return frepcore.exit_status_of(e)
    except (KeyboardInterrupt, frepcore.Cancelled) as e:
        sys.stderr.write("\nfrepcad: cancelled; nothing written\n")
        return frepcore.exit_status_of(e)
    except Exception as e:  # a bad model or option, a file, the scheduler, a job that failed
        # (the cluster's own failures, a worker killed or a scheduler gone, are no bug here)
        sys.stderr.write("frepcad: %s\n" % (str(e) or type(e).__name__))
        return frepcore.EXIT_STATUS["bad_input"]
    if show:
        sys.stderr.write("\n")
    if not quiet:
        seconds = [j["seconds"] for j in report["jobs"]]
        workers = len({j["pid"] for j in report["jobs"]})
        split = "x".join(str(s) for s in report["split"])
        print("meshed %s as %d brick jobs (%s) on %d workers: %d triangles, jobs %.2f-%.2f s "
              "(merge %.2f s, check %.2f s%s)"
              % (args["model"], len(seconds), split, workers, report["triangles"],
                 min(seconds), max(seconds), report["seconds"][1], report["seconds"][2],
                 ", piece by piece" if report.get("checked_in_parts") else ""))
        print(report["text"], end="")
        print("wrote %s" % args["output"])
    return frepcore.EXIT_STATUS["not_printable" if report["printable"] is False else "done"]


if __name__ == "__main__":
    sys.exit(main())
