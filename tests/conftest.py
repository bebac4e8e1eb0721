"""Test configuration: property tests are derandomized, so that a test run is reproducible
(the same examples every time, on every machine) and CI cannot fail by chance."""

from hypothesis import settings

settings.register_profile("saxum", derandomize=True, deadline=None)
settings.load_profile("saxum")
