"""Hypothesis profiles, loaded as a pytest plugin: ``pytest -p tests.hypothesis_profiles``.

``--hypothesis-profile=mutation`` (used by ``benchmarks/mutation.sh``) makes
the property tests reproducible from one mutant to the next: derandomised
examples, so that a mutant's verdict does not depend on the draw, and no
example database, so that a failure found on one mutant is not replayed on
the next. Tests that set ``max_examples`` themselves keep their own count;
the profile's count applies to the others.
"""

from hypothesis import settings

settings.register_profile("mutation", max_examples=10, derandomize=True, database=None, deadline=None)
