"""Each kind's model for inspecting a scan of it (camfab.inspect.surface.ScanModel)."""
