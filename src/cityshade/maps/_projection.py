"""Longitude/latitude -> local metres: the UTM zone of the data's centre, shifted so the centre is (0, 0).

Beyond the UTM band (|latitude| > 84) a transverse Mercator about the centre is used instead.
Data already in metres (a GeoJSON or CityJSON without a geographic system) keeps its units and is
only shifted to its centre; its CRS reads "local".
"""

from __future__ import annotations

import numpy as np
import pyproj
import shapely

LOCAL = "local"


def in_range(lon, lat) -> np.ndarray:
    """True where (lon, lat) is a finite point on the Earth."""
    lon, lat = np.asarray(lon, dtype=np.float64), np.asarray(lat, dtype=np.float64)
    return np.isfinite(lon) & np.isfinite(lat) & (np.abs(lon) <= 180.0) & (np.abs(lat) <= 90.0)


def utm_crs(lon: float, lat: float) -> str:
    if abs(lat) > 84.0:
        return f"+proj=tmerc +lat_0={lat:.7f} +lon_0={lon:.7f} +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m +no_defs"
    zone = min(int((lon + 180.0) // 6.0) + 1, 60)
    return f"EPSG:{(32600 if lat >= 0 else 32700) + zone}"


class Projection:
    """Maps points of `source_crs` to metres about `centre` (given in source units). Raises ValueError
    when the centre is not on the Earth in that system, pyproj's CRSError when it cannot be used."""

    def __init__(self, centre: tuple[float, float], source_crs: str | pyproj.CRS = "EPSG:4326"):
        source = pyproj.CRS.from_user_input(source_crs)
        if source.is_compound:  # e.g. RD New + NAP height: the plan position is the first part
            source = source.sub_crs_list[0]
        to_geographic = pyproj.Transformer.from_crs(source, "EPSG:4326", always_xy=True)
        lon, lat = to_geographic.transform(*centre)
        if not in_range(lon, lat):
            raise ValueError(f"the centre {centre[0]:.6g}, {centre[1]:.6g} is not on the Earth in {source.name}")
        self.origin = (float(lon), float(lat))
        self.crs = utm_crs(lon, lat)
        self._transformer = pyproj.Transformer.from_crs(source, self.crs, always_xy=True)
        self._offset = np.asarray(self._transformer.transform(*centre), dtype=np.float64)

    def points(self, xy: np.ndarray) -> np.ndarray:
        """(n, 2) source coordinates -> (n, 2) local metres."""
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        x, y = self._transformer.transform(xy[:, 0], xy[:, 1])
        return np.stack([x, y], axis=1) - self._offset

    def geometries(self, geometries):
        """Shapely geometries (an array or list) projected in one call."""
        return shapely.transform(np.asarray(geometries, dtype=object), self.points)


class LocalMetres:
    """Coordinates already in metres: only moved so that `centre` is (0, 0)."""

    crs = LOCAL
    origin = (0.0, 0.0)

    def __init__(self, centre: tuple[float, float]):
        self._offset = np.asarray(centre, dtype=np.float64)

    def points(self, xy: np.ndarray) -> np.ndarray:
        return np.asarray(xy, dtype=np.float64).reshape(-1, 2) - self._offset

    def geometries(self, geometries):
        return shapely.transform(np.asarray(geometries, dtype=object), self.points)
