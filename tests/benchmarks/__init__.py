"""The performance benchmark (`scripts/bench`) and the soak run (`scripts/bench soak`).

Not a test suite: nothing here is collected by pytest (no `test_` files). It runs the
simulated PLC with a latency model, the TecoApi client, a baseline client doing what
the existing public TecoApi integration does, and a real Home Assistant instance, all
in one process, and reports requests, wall time, CPU, memory and write latency. The
deterministic counts it reports are asserted in `tests/test_bench_counts*.py`.
"""
