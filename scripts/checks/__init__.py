"""What HACS's and hassfest's validators check, runnable where they cannot run.

Neither validator runs here (no network, no Docker), so these modules check what
they check, plus what Home Assistant's own test suite checks at runtime for core
integrations: every translation key the code uses exists in each translation, and
translations, icons, services and brand images agree with each other and with the
code.

Each checker returns a list of problems in words, so a failing test names all of
them at once. By concern:

- `common`: reading JSON and YAML, walking nested objects by key path;
- `hacs`: HACS's checks of the tree (the licence, hacs.json, the manifest's keys,
  the brand icon, the README, the layout); `manifest`: manifest.json and
  const.DOMAIN (hassfest's rules);
- `translations`: one translation file's keys and strings, two files in step;
- `scope`, `reader`: what the integration's Python code asks of its translations
  and services.yaml (read with `ast`, never imported); `usage`: those needs
  against a translation; `descriptors`: what a source descriptor's forms need;
- `services`: services.yaml; `icons`: icons.json; `brand`: the brand images;
- `quality_scale`: Home Assistant's quality-scale validators (hassfest's), on the
  rules quality_scale.yaml marks done.

tests/test_packaging.py applies them to this repository; tests/checks feeds each
one small bad input, to show each rule can fail.
"""
