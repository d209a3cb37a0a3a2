"""Rule figures: every PNG of the sweep (bearing_envelope.study.figures.make_figures)."""
import json
from pathlib import Path

from bearing_envelope.study.figures import make_figures
from bearing_envelope.study.pipeline import log_to
from bearing_envelope.study.job_transport import job_settings

inp = snakemake.input  # noqa: F821
with log_to(snakemake.log[0]) as log:  # noqa: F821
    written = make_figures(
        harmonics=inp.harmonics,
        cases=inp.cases,
        bands=inp.bands,
        case_files={Path(p).stem: p for p in inp.case_files},
        kurtogram_files={Path(p).stem.removesuffix("_kurtogram"): p for p in inp.kurtograms},
        spectra_files={Path(p).stem: p for p in inp.spectra},
        example=snakemake.params.example,  # noqa: F821
        analysis=job_settings(snakemake).analysis,  # noqa: F821
        outdir=snakemake.output[0],  # noqa: F821
    )
    print("\n".join(map(str, written)), file=log)
