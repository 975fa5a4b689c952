"""Where scenarios run.

local[:N]        a pool of N worker processes on this machine (default: one
                 per core); each runs plcrun.
dask://HOST:PORT a Dask distributed scheduler (dask-scheduler, dask-worker on
                 any number of machines); each task runs plcrun on its worker.
                 A worker that dies mid-scenario loses its task, and the
                 scheduler gives it to another worker; each scenario's result
                 is taken once (ResultStore keys it by hash), so a retried
                 scenario never appears twice.

Both yield result records as scenarios finish, in any order.
"""

import concurrent.futures as cf
import os

from . import scenario_run


def parse(spec):
    if spec is None or spec == "local":
        return ("local", os.cpu_count() or 1)
    if spec.startswith("local:"):
        n = int(spec.split(":", 1)[1])
        if n < 1:
            raise ValueError("local:N needs N >= 1")
        return ("local", n)
    if spec.startswith("dask://"):
        return ("dask", "tcp://" + spec[len("dask://"):])
    raise ValueError("unknown executor '%s' (local, local:N, dask://HOST:PORT)" % spec)


def run_local(tasks, jobs):
    if jobs == 1:
        for t in tasks:
            yield scenario_run.run_scenario(t)
        return
    with cf.ProcessPoolExecutor(max_workers=jobs) as pool:
        futures = [pool.submit(scenario_run.run_scenario, t) for t in tasks]
        try:
            for f in cf.as_completed(futures):
                yield f.result()
        except BaseException:
            for f in futures:
                f.cancel()
            raise


def run_dask(tasks, address, retries=3):
    # Imported here: the local executor needs no Dask.
    import cloudpickle
    from distributed import Client, as_completed

    # Workers get run_scenario by value: they need Python, Dask and plcrun,
    # not this package.
    cloudpickle.register_pickle_by_value(scenario_run)
    with Client(address, timeout="30s") as client:
        futures = [client.submit(scenario_run.run_scenario, t, key="scenario-" + t["hash"],
                                 pure=False, retries=retries) for t in tasks]
        for f in as_completed(futures):
            yield f.result()
            f.release()
