"""A pytest plugin for mutants' runs: Hypothesis finds a failure, and stops there.

No shrinking (a mutant only needs to fail, not a minimal example) and no example
database (a mutant's failures are no example for the real code).
"""

from hypothesis import Phase, settings

settings.register_profile(
    "mutate",
    database=None,
    phases=(Phase.explicit, Phase.reuse, Phase.generate),
    print_blob=False,
)
settings.load_profile("mutate")
