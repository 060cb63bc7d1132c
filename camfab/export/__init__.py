"""Format writers and readers: DXF, SVG, STL, the report (JSON, HTML, figures) and the motion
table, each serialising a kind's part (:mod:`camfab.export.part`) or an analysis into the bytes
of one file; the pipeline writes them."""
