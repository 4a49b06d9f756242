"""The demo's tables as files and on the console: each one's title and column legend.

The legends repeat the prose of docs/RESULTS.md, so a file under build/demo/ read alone
explains itself; the pages themselves get the bare tables (demo.update_page).
"""
from __future__ import annotations

from pathlib import Path

from md_tables import console_table, markdown_doc

# name: (title, key columns repeated in every console group, column legend)
TABLE_DOCS = {
    "accuracy": ("Accuracy of the paper configuration (SCKF, Dugoff truth)", 2, [
        ("RMSE fl … rr", "RMSE of μ per wheel over the settled samples (t ≥ 1 s, not within "
         "0.5 s after a change of the true μ)"),
        ("max err", "largest |error| over wheels and settled samples"),
        ("max rel", "largest |error| / μ_true"),
        ("mean-μ RMSE", "RMSE of the four-wheel mean"),
        ("t_conv", "latest time (over wheels) from which |error| ≤ 0.05 holds to the end "
         "(never: it does not)"),
        ("mean sd", "the filter's own standard deviation, mean over wheels and t ≥ 1 s"),
        ("Δref SCKF / CKF", "largest |μ − μ_reference| of the float32 SCKF / CKF against the "
         "float64 reference estimate logs (– without one)"),
        ("Δref q31 SCKF / CKF", "the same for the fixed-point estimator (--real q31)")]),
    "trust": ("Trustworthiness: default vs paper preset, both truth tyres", 4, [
        ("class", "excited (tyres near their limit), steering, never (friction not observable), "
         "wrong tyre (the car's tyre is not its parameter file's)"),
        ("truth", "the simulator's truth tyre: MF (Magic Formula) or Dugoff"),
        ("RMSE / max err fl/fr/rl/rr", "per wheel over the settled samples"),
        ("mean-μ RMSE", "RMSE of the four-wheel mean"),
        ("RMSE valid", "RMSE over the settled samples reported valid"),
        ("valid", "share of the settled samples reported valid"),
        ("excited valid", "share of the samples with true utilisation ≥ 0.5 reported valid"),
        ("consistency", "share of the settled samples with |error| ≤ 2·sd (honest: near 95 %)"),
        ("re-conv", "worst time to come back within 0.05 after a change of the true μ"),
        ("Δμ q31", "largest |μ_q31 − μ_double| of that configuration over the settled samples")]),
    "headline": ("Headline: default preset on the Magic Formula truth", 1, [
        ("RMSE when valid", "RMSE over the settled samples reported valid"),
        ("excited samples valid", "share of the samples with true utilisation ≥ 0.5 reported "
         "valid"),
        ("settled samples valid", "share of the settled samples reported valid (for the "
         "never-excited logs every one is a false claim)"),
        ("…, observer", "the same with vx, vy and the yaw acceleration from the velocity "
         "observer, as in a production car"),
        ("never excited", "one row for those logs together, each column the worst of them")]),
    "q31": ("Fixed point (q31) against double", 1, [
        ("paper SCKF / paper CKF / default none/default/MF", "largest |μ_q31 − μ_double| over "
         "the settled samples of the noise-free / default-noise / Magic Formula log"),
        ("valid agree", "smallest share of (sample, wheel) pairs whose valid flags agree"),
        ("saturations", "estimator and input saturation counts, summed")]),
}


def write_table(out_dir: Path, name: str, lines: list[str], written: list[tuple[str, Path]]
                ) -> None:
    """The table as out_dir/<name>.md (titled, with its column legend) and on the console
    (at most md_tables.CONSOLE_WIDTH wide); remembered in written for the index."""
    title, keep, legend = TABLE_DOCS[name]
    path = out_dir / f"{name}.md"
    path.write_text(markdown_doc(title, lines, legend))
    print()
    print("\n".join(console_table(title, lines, keep=keep)))
    print(f"(full table: {path})")
    written.append((title, path))
