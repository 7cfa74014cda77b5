"""The resumable runner of studies and assessments: a table appended row by row (the resume record)
and the execution of a module-level task over points on a local process pool, a local Dask cluster
or a Dask scheduler (which receives the FMU file itself)."""
import csv
import hashlib
import os
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path


class Table:
    """The study's CSV, appended row by row (the resume record)."""

    def __init__(self, path, columns):
        self.path = Path(path)
        self.columns = columns
        self.done = {}
        if self.path.exists() and self.path.stat().st_size:
            with self.path.open(newline="") as handle:
                reader = csv.DictReader(handle)
                rows = list(reader) if reader.fieldnames == list(columns) else None
            if rows is None:  # written by another version: kept aside, not appended to
                self.path.replace(self.path.with_suffix(".stale.csv"))
            for row in rows or ():
                self.done[row["key"]] = row
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fresh = not self.done
        self.handle = self.path.open("a" if not fresh else "w", newline="")
        self.writer = csv.DictWriter(self.handle, fieldnames=columns, extrasaction="ignore")
        if fresh:
            self.writer.writeheader()
            self.handle.flush()

    def add(self, row):
        self.writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})
        self.handle.flush()
        self.done[row["key"]] = row

    def close(self):
        self.handle.close()


def run_table(task, todo_all, keys, table, engine, path, workers, dask, scheduler, progress, desc, cost=None):
    """Run task(point, engine, path) for every point whose key is not in `table` yet, adding each
    row as it finishes (the resume record), with a progress bar on a terminal; closes the table.
    `cost(point)`: its expected cost; the costliest are sent first (longest processing time first:
    the workers do not wait at the end on one long task started last)."""
    from tqdm import tqdm

    todo = [p for p, k in zip(todo_all, keys) if k not in table.done]
    if cost is not None:
        todo.sort(key=cost, reverse=True)
    bar = tqdm(total=len(todo_all), initial=len(todo_all) - len(todo), disable=None if progress else True,
               desc=desc, unit="run", file=sys.stderr)
    try:
        for row in execute(task, todo, engine, path, workers, dask, scheduler):
            table.add(row)
            bar.update(1)
    finally:
        bar.close()
        table.close()


def execute(task, todo, engine, path, workers=None, dask=False, scheduler=None):
    """Yield task(point, engine, path) for every point of `todo` as they finish: on a local process
    pool (default, `workers` processes), a local Dask cluster (dask) or a Dask scheduler, which
    receives the FMU file itself.  `task` must be a module-level function (it is pickled)."""
    if not todo:
        return
    with Pool(path, workers, dask, scheduler) as pool:
        yield from pool.run(task, todo, engine)


class Pool:
    """A local process pool, a local Dask cluster or a Dask scheduler's client, open over several
    rounds of tasks (a search's batches); with Dask the FMU at `path` is shipped to the workers
    once."""

    def __init__(self, path, workers=None, dask=False, scheduler=None):
        self.path, self.workers, self.dask = path, workers or os.cpu_count(), bool(dask or scheduler)
        self.scheduler = scheduler
        self.pool = self.client = self.cluster = self.shipped = None

    def __enter__(self):
        if not self.dask:
            self.pool = ProcessPoolExecutor(max_workers=self.workers)
            return self
        from dask.distributed import Client, LocalCluster

        if self.scheduler:
            self.client = Client(self.scheduler)
        else:
            self.cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                        dashboard_address=None)
            self.client = Client(self.cluster)
        if self.path is not None:
            data = Path(self.path).read_bytes()
            self.shipped = (self.client.scatter(data, broadcast=True), hashlib.sha256(data).hexdigest()[:16])
        return self

    def run(self, task, todo, engine):
        """Yield task(point, engine, path) for every point of `todo` as they finish."""
        if self.pool is not None:
            futures = [self.pool.submit(task, p, engine, self.path) for p in todo]
            for future in as_completed(futures):
                yield future.result()
            return
        from dask.distributed import as_completed as dask_completed

        if self.shipped is not None:
            futures = [self.client.submit(_run_shipped, task, p, engine, *self.shipped, pure=False) for p in todo]
        else:
            futures = [self.client.submit(task, p, engine, None, pure=False) for p in todo]
        for future in dask_completed(futures):
            yield future.result()

    def __exit__(self, *exc):
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)
        if self.client is not None:
            self.client.close()
        if self.cluster is not None:
            self.cluster.close()


def write_parquet(csv_path, parquet_path):
    import pyarrow.csv as pacsv
    import pyarrow.parquet as pq

    pq.write_table(pacsv.read_csv(csv_path), parquet_path)


def _run_shipped(task, point, engine, fmu_bytes, digest):
    """A worker's task: write the shipped FMU once per digest, then task(point, engine, path)."""
    path = Path(tempfile.gettempdir()) / f"pidamper-{digest}.fmu"
    if not path.exists():
        tmp = path.with_suffix(f".{os.getpid()}.part")
        tmp.write_bytes(fmu_bytes)
        tmp.replace(path)
    return task(point, engine, path)


def add_runner_arguments(parser):
    """--engine, --workers, --dask, --scheduler, --fmu: how the runs of a study or an assessment go."""
    parser.add_argument("--engine", choices=("fmu", "core"), default="fmu",
                        help="run the FMU through fmpy (default) or the physics core directly")
    parser.add_argument("--workers", type=int, help="processes (default: one per core)")
    parser.add_argument("--dask", action="store_true", help="use a local Dask cluster")
    parser.add_argument("--scheduler", help="Dask distributed scheduler address, e.g. tcp://host:8786")
    parser.add_argument("--fmu", help="FMU file (default: build or reuse dist/PendulumImpactDamper.fmu)")
