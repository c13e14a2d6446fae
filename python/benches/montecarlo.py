"""Monte Carlo from Python, measured side by side in one process (ratios, not timed tests).

10,000 members of a case-A-like free body (the paper's J_d = (1.3, 2.1, 1.2), so
J = diag(3.3, 2.5, 3.4); start rates (-2, 1.9, -1) dispersed by 0.02 rad/s, the principal
moments by 1% truncated at 3%), T = 100, h = 0.5, n = 16, 100 sample times:

1. scaling: the local run on one thread against two (rayon inside one process);
2. Dask: the same run as chunks of 500 members on a ``LocalCluster`` of two worker
   processes (one thread each) on loopback, against the local two-thread run; the arrays
   and percentiles of the two are compared for bit identity.

Run after ``pip install ./python`` with ``dask[distributed]``:
    python python/benches/montecarlo.py [members]
Each time is the median of ``REPEATS`` runs.
"""

import statistics
import sys
import time

import numpy as np

import lgsvi
from lgsvi import montecarlo as mc

REPEATS = 3
FIELDS = ("member", "ok", "inertia", "attitude0", "omega0", "torque", "t", "attitude", "omega", "energy")


def timed(f):
    times, result = [], None
    for _ in range(REPEATS):
        start = time.perf_counter()
        result = f()
        times.append(time.perf_counter() - start)
    return statistics.median(times), result


def main():
    from dask.distributed import Client, LocalCluster

    members = int(sys.argv[1]) if len(sys.argv) > 1 else 10_000
    body = lgsvi.RigidBody(inertia_d=[1.3, 2.1, 1.2])
    spec = {"omega": mc.normal(0.02), "inertia": mc.truncated_normal(0.01, 0.03)}
    args = (body, np.eye(3), [-2.0, 1.9, -1.0], spec)
    kw = dict(members=members, seed=2026, t_end=100.0, h=0.5, nodes=16, samples=100)
    one, _ = timed(lambda: mc.run(*args, threads=1, **kw))
    two, local = timed(lambda: mc.run(*args, threads=2, **kw))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=None) as cluster, Client(cluster) as client:
        mc.run(*args, client=client, **dict(kw, members=10))  # workers import lgsvi
        dask, remote = timed(lambda: mc.run(*args, client=client, chunk_size=500, **kw))
    same = all(np.array_equal(getattr(local, f), getattr(remote, f), equal_nan=True) for f in FIELDS)
    same_percentiles = all(
        np.array_equal(local.envelope.percentile(q), remote.envelope.percentile(q), equal_nan=True)
        for q in (1, 50, 99)
    )
    print(f"{members} members, T = 100, h = 0.5, n = 16, failed: {len(local.errors)}")
    print(f"local, 1 thread:   {one:7.2f} s  ({members / one:8.0f} members/s)")
    print(f"local, 2 threads:  {two:7.2f} s  (scaling {one / two:.2f}x)")
    print(f"Dask, 2 workers:   {dask:7.2f} s  (overhead {100 * (dask / two - 1):+.1f}% against local)")
    print(f"Dask result identical to local: arrays {same}, percentiles {same_percentiles}")


if __name__ == "__main__":
    main()
