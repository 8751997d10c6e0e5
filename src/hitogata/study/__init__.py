"""Population studies: many bodies through many motions, on dask.distributed (docs/study.md).

`spec.load_study` reads a study file, `runner.plan` makes its (body, motion)
tasks, `tasks.execute` runs one anywhere, `runner.run_on_client` runs them on
a Dask cluster (`runner.run_serial`: in a plain loop), `results` turns the rows
into percentile tables and `plots` draws them.
"""
