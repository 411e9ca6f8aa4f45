"""raster: the paper's pixel method for r-tightening (constrained level-set curvature flow)."""

__all__: list[str] = []
