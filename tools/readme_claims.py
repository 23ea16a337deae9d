"""Rewrite the claims tables of README.md from a claims.json written by
`smodrive reproduce` (the tables sit between `<!-- claims:PAPER -->` and
`<!-- /claims:PAPER -->` markers, the pass/fail counts between
`<!-- count:PAPER -->` markers).

    python tools/readme_claims.py results/claims.json [--readme README.md]

A failing claim's short reason comes from SHORT below; a failing claim that
has none there stops the script, so that a new failure is explained by hand.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SHORT = {
    "yang2018.fig1.sim_peak_gain_db_Lhat_2L_vs_eq14": "eq. (14) assumes the Euler plant",
    "yang2018.fig5a.eq12_vs_exact": "eq. (12) assumes the Euler plant (errata E13)",
    "yang2018.fig7b.pos_error_peak_deg": "ADC noise and dead time at 75 r/min",
    "yang2018.fig7b.pos_error_peak_deg_oversampled": "dead time alone gives 10.5 deg",
    "yang2018.fig9.pos_error_peak_deg": "dead time at 72-150 r/min without load (noise off: "
                                        "14.4 deg)",
    **{f"yao2022.table5.ripple_rpm_{law}_{t}": "the PLL (50) cannot pass such ripple (errata Y12)"
       for law in ("baseline", "proposed") for t in ("30k", "60k", "100k")},
    "yao2022.table5.ripple_reduction_100k": "ripple made by ADC noise and quantisation, alike "
                                            "for both laws (0.66 without them; errata Y12)",
    **{f"yao2022.fig10.pos_error_vs_paper_rad_{t}": "no dead time simulated: 35 ns uncompensated "
       "give the paper's 30 and 60 kr/min readings (errata Y13)" for t in ("30k", "60k")},
    "yao2022.fig14.pos_error_peak_rad": "PLL takes up the assumed ramp slowly",
    "yao2022.fig14.pos_error_peak_rad_adc": "ADC noise at 5-10 kr/min",
    "yao2022.fig14.end_speed_rpm": "inverter voltage limit",
    "yao2022.fig22.reversal_pos_error_peak_rad": "ADC noise at 3-5 kr/min: no seed within 0.1 "
                                                 "rad (0.069 without the noise)",
    "yao2022.fig22.crossing_pos_error_peak_rad": "no back EMF within +-3 kr/min",
    "yao2022.fig23.linear_observer_stable": "linear observer keeps its poles",
    "yao2022.fig4.comp_error_ratio_18_over_17": "periodic disturbance is the 2 f_e line alone",
    "yao2022.table6.cycles_worst_call": "the step exceeds the 50 us period at its worst",
}


def _num(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float) and v != 0.0 and (abs(v) < 1e-3 or abs(v) >= 1e5):
        return f"{v:.2e}"
    return f"{v:.4g}" if isinstance(v, float) else str(v)


#: the kinds of claim (smodrive.claims.KINDS), as the README's counts name them
KIND_WORDS = {"paper": "against the paper's numbers", "equation": "against its own equations",
              "method": "method checks", "analytic": "analytic checks (not counted)"}


def counts(mine: list[dict]) -> str:
    """The README's counts of one paper, by kind."""
    parts = []
    for kind, words in KIND_WORDS.items():
        of = [c for c in mine if c.get("kind", "method") == kind]
        if of:
            n_pass = sum(c["passed"] for c in of)
            parts.append(f"{words}: {n_pass} of {len(of)} pass")
    return "**" + "; ".join(parts) + "**"


def table(claims: list[dict], paper: str) -> str:
    rows = [f"| claim (`{paper}.`) | kind | paper | expected | reproduced | unit | criterion | "
            "result |",
            "|---|---|---|---|---|---|---|---|"]
    for c in claims:
        if not c["id"].startswith(paper + "."):
            continue
        if c["passed"]:
            result = "pass"
        elif c["id"] in SHORT:
            result = f"**fail**: {SHORT[c['id']]}"
        else:
            sys.exit(f"{c['id']} fails and has no short reason in SHORT: add one")
        crit = (c["criterion"].replace("reproduced", "rep").replace("expected", "exp")
                .replace("|", "\\|"))
        rows.append(f"| `{c['id'][len(paper) + 1:]}` | {c.get('kind', 'method')} | "
                    f"{_num(c['paper'])} | "
                    f"{_num(c['expected'])} | {_num(c['reproduced'])} | {c['unit']} | {crit} | "
                    f"{result} |")
    return "\n".join(rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("claims", type=Path)
    ap.add_argument("--readme", type=Path, default=ROOT / "README.md")
    a = ap.parse_args()
    claims = json.loads(a.claims.read_text())
    text = a.readme.read_text()
    for paper in ("yang2018", "yao2022"):
        mine = [c for c in claims if c["id"].startswith(paper + ".")]
        count = counts(mine)
        for tag, body in ((f"claims:{paper}", table(claims, paper)), (f"count:{paper}", count)):
            pat = re.compile(rf"(<!-- {tag} -->)(.*?)(<!-- /{tag} -->)", re.S)
            if not pat.search(text):
                sys.exit(f"{a.readme}: no <!-- {tag} --> ... <!-- /{tag} --> markers")
            sep = "\n" if tag.startswith("claims") else ""
            text = pat.sub(lambda m: m.group(1) + sep + body + sep + m.group(3), text)
    a.readme.write_text(text)
    print(f"{a.readme}: claims tables rewritten from {a.claims}")


if __name__ == "__main__":
    main()
