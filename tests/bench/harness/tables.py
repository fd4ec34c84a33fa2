"""The benchmark's tables: which porter-plan runs make each, and the obstacles Table II reports.

A run is (table, scene, parameter overrides, method, seed). Methods map to porter-plan flags:
  kc_svsdf        ours: kernel front-end, KC-SVSDF back-end
  svsdf_per_link  the ablation baseline: each link's SVSDF alone in the back-end
  spheres         the REMANI/TOPAY-style baseline: bounding spheres against a Euclidean distance
                  field in the front-end and as the back-end's safety term
"""

METHOD_FLAGS = {
    "kc_svsdf": ["--safety", "kc_svsdf"],
    "svsdf_per_link": ["--safety", "svsdf_per_link"],
    "spheres": ["--collision", "spheres"],
}

# Table II: the three hardest obstacles of each scene. Each entry is (label, names): the
# clearance reported is the least over the named obstacles of the scene file (a name ending in
# "." matches every obstacle it prefixes, e.g. the three boxes a bridge expands into).
HARDEST = {
    "bridge": [("deck", ["bridge_hole.deck"]), ("left wall", ["bridge_hole.left_wall"]),
               ("right wall", ["bridge_hole.right_wall"])],
    "tunnel": [("low beam", ["low_beam.deck"]), ("column gate", ["gate_left", "gate_right"]),
               ("bridge hole", ["hole."])],
    "forest": [("hole 1", ["hole_1."]), ("hole 2", ["hole_2."]), ("hole 3", ["hole_3."])],
}


def table_definitions(quick):
    """Returns the run groups of every table. quick: a small subset of each (smoke run)."""
    hb = ["1.0", "0.8"] if quick else ["1.1", "1.0", "0.9", "0.8"]
    return {
        "table1": {
            "title": "Table I: ablation on the bridge (T payload)",
            "stages": "full", "budgets": {"frontend": 80, "midend": 100, "backend": 300},
            "seeds": 2 if quick else 20,
            "groups": [{"scene": "bridge", "sets": {"h_b": v}, "label": "h_b=%s" % v} for v in hb],
            "methods": ["kc_svsdf", "svsdf_per_link", "spheres"],
        },
        "table3": {
            "title": "Table III: comparison on tunnel (T payload) and forest (long bar)",
            "stages": "full", "budgets": {"frontend": 1000, "midend": 100, "backend": 300},
            "seeds": 2 if quick else 100,
            "groups": [{"scene": "tunnel", "sets": {}, "label": "tunnel"},
                       {"scene": "forest", "sets": {}, "label": "forest"}],
            "methods": ["kc_svsdf", "spheres"],
        },
        # Stage benchmarks (not paper tables): run with --table frontend / --table midend.
        "frontend": {
            "title": "Front-end alone (porter-plan --stages front)",
            "stages": "front", "budgets": {"frontend": None, "midend": 100, "backend": 300},
            "seeds": 5 if quick else 100,
            "groups": [{"scene": "bridge", "sets": {"h_b": v}, "label": "h_b=%s" % v, "frontend_budget": 80}
                       for v in ["1.1", "1.0", "0.9", "0.8"]] +
                      [{"scene": "tunnel", "sets": {}, "label": "tunnel", "frontend_budget": 1000},
                       {"scene": "forest", "sets": {}, "label": "forest", "frontend_budget": 200}],
            "methods": ["kc_svsdf"],
        },
        "midend": {
            "title": "Front-end and mid-end (porter-plan --stages mid), validated",
            "stages": "mid", "budgets": {"frontend": 1000, "midend": 100, "backend": 300},
            "seeds": 3 if quick else 20,
            "groups": [{"scene": s, "sets": {}, "label": s} for s in ["bridge", "tunnel", "forest"]],
            "methods": ["kc_svsdf"],
        },
    }


DEFAULT_TABLES = ["table1", "table3"]


def hardest_clearance(scene, clearances):
    """[(label, least clearance m or None, exact)] for the scene's hardest obstacles, from a
    porter-validate report's clearance list."""
    out = []
    for label, names in HARDEST.get(scene, []):
        best, exact = None, True
        for c in clearances:
            name = c["obstacle"]
            if not any(name == n or (n.endswith(".") and name.startswith(n)) for n in names):
                continue
            if c["min_m"] is not None and (best is None or c["min_m"] < best):
                best, exact = c["min_m"], c.get("exact", True)
        out.append((label, best, exact))
    return out
