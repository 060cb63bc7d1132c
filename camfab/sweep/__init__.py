"""Design sweeps (``camfab sweep``): the variants of one design over a product of varied keys
(or a CSV of them), each validated and analysed without files into one row of key numbers, run
in batches on a local process pool or a Dask cluster, written as a table (Parquet with the
``sweep`` extra, else CSV) and a summary page; the best few built in full.

- :mod:`camfab.sweep.vary` — the ``--vary PATH=SPEC`` options and ``--variants`` files, and a
  variant's design data;
- :mod:`camfab.sweep.rows` — one variant's row;
- :mod:`camfab.sweep.engines` — the batches run locally or on Dask, rows back in order;
- :mod:`camfab.sweep.table` — the table written as rows arrive, atomically;
- :mod:`camfab.sweep.page` — the summary page;
- :mod:`camfab.sweep.run` — a sweep end to end.
"""
