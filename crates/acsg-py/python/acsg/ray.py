"""Graphs of many pairs on a Ray cluster: ``acsg.ray.generate_many(tasks)``.

Each pair is one Ray task (``ray.remote``) running :func:`acsg.generate` on a worker
with as many threads as the task reserves CPUs; the driver gets the graph's JSON back
and returns, in the order of ``tasks``, a :class:`acsg.Graph` or the exception that
pair raised, as :func:`acsg.generate_many` does on one machine. Parts given as paths
must be readable by the workers (a shared file system, or the same paths on every
node); parts given as arrays or trimesh meshes travel with the task. ::

    import ray, acsg, acsg.ray
    ray.init()                                  # or ray.init(address="auto")
    graphs = acsg.ray.generate_many(tasks, num_cpus=2)

Ray is not a dependency of acsg: install it where you use this module.
"""

from __future__ import annotations

from typing import Any, Iterable, List, Mapping, Optional, Tuple, Union

import acsg


def _run(task: Mapping[str, Any], threads: int) -> Tuple[str, Any]:
    """On a worker: ``("graph", json)`` or ``("error", exception)``."""
    arguments = dict(task)
    arguments.setdefault("threads", threads)
    try:
        return ("graph", acsg._one(arguments).to_json())
    except Exception as error:  # each pair's error is its result
        return ("error", error)


def generate_many(
    tasks: Iterable[Mapping[str, Any]],
    num_cpus: int = 1,
    progress: bool = False,
    **options: Any,
) -> List[Union[acsg.Graph, Exception]]:
    """Generates the graphs of many pairs as Ray tasks.

    :param tasks: each a dict of :func:`acsg.generate`'s arguments, optionally with
        ``output`` (see :func:`acsg.generate_many`; the path is the worker's).
    :param num_cpus: CPUs each pair reserves; its run uses as many threads (unless the
        task gives ``threads``).
    :param progress: one progress bar (tqdm when installed) over the pairs as they end.
    :param options: further ``ray.remote`` options (``memory``, ``resources``, ...).
    :returns: in the order of ``tasks``, a :class:`acsg.Graph` per pair or the
        exception it raised.
    """
    import ray

    if not ray.is_initialized():
        ray.init()
    remote = ray.remote(_run).options(num_cpus=num_cpus, **options)
    refs = [remote.remote(dict(task), num_cpus) for task in tasks]
    bar: Optional[Any] = None
    if progress:
        try:
            from tqdm.auto import tqdm

            bar = tqdm(total=len(refs), unit="pair", desc="acsg")
        except ImportError:
            bar = None
    pending = list(refs)
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        if bar is not None:
            bar.update(len(done))
    if bar is not None:
        bar.close()
    results: List[Union[acsg.Graph, Exception]] = []
    for ref in refs:
        try:
            kind, value = ray.get(ref)
        except Exception as error:  # the worker died, or Ray failed to run the task
            results.append(error)
            continue
        results.append(acsg.Graph(value) if kind == "graph" else value)
    return results
