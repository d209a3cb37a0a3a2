"""Rule diagnosability: the detection table of the sweep, its measured false-alarm rates and one
heat map per band strategy."""
import pandas as pd

from bearing_envelope.diagnosis.detection import false_alarm_rates
from bearing_envelope.study.figures import fig_diagnosability_maps
from bearing_envelope.study.paper import write_page
from bearing_envelope.study.pipeline import log_to
from bearing_envelope.io import write_csv_atomic
from bearing_envelope.study.tables import add_location, table_html

with log_to(snakemake.log[0]) as log:  # noqa: F821
    inp, out = snakemake.input, snakemake.output  # noqa: F821
    df = add_location(pd.concat([pd.read_csv(p) for p in inp.cells], ignore_index=True),
                      snakemake.params.cases)  # noqa: F821  (the sweep's typed cases)
    df = df.sort_values(["band"] + (["location"] if "location" in df else [])
                        + ["load_kN", "depth_um", "snr_db"], kind="stable")
    write_csv_atomic(df, out.table)
    trials = pd.concat([pd.read_csv(p) for p in inp.false_alarms], ignore_index=True)
    rates = pd.concat([false_alarm_rates(trials, by=["band", "snr_db"]),
                       false_alarm_rates(trials, by=["band"]).assign(snr_db="all"),
                       false_alarm_rates(trials, by=[]).assign(band="all", snr_db="all")],
                      ignore_index=True)
    write_csv_atomic(rates, out.false_alarms)
    print(rates.to_string(), file=log)
    fig_diagnosability_maps(df, out.maps)
    # the same two tables viewable in the report (written to a temporary folder, then renamed)
    import shutil
    from pathlib import Path

    pages = Path(out.pages)
    tmp = pages.with_name(pages.name + ".tmp")
    tmp.mkdir(parents=True, exist_ok=True)
    write_page(table_html({"diagnosability": df}, "diagnosability.csv",
                          "BPFI detection per case, SNR and band."), tmp / "diagnosability.html")
    write_page(table_html({"false_alarms": rates}, "false_alarms.csv",
                          "Measured false-alarm rate of the detection test on the healthy cases "
                          "(95 % Clopper-Pearson interval); design 1 %."), tmp / "false_alarms.html")
    shutil.rmtree(pages, ignore_errors=True)
    tmp.rename(pages)
