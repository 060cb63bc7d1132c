"""Exporters: each turns an analysis into the bytes of one file; the pipeline writes them."""
