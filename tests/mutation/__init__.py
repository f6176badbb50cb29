"""Mutation testing of the library's codecs, address parsers and planners (scripts/mutate)."""
