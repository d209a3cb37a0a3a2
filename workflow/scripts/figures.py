"""Rule figures: every PNG of the sweep (bearing_envelope.figures.make_figures)."""
import json

from bearing_envelope.figures import make_figures
from bearing_envelope.pipeline import log_to

with log_to(snakemake.log[0]) as log:  # noqa: F821
    written = make_figures(
        harmonics=snakemake.input.harmonics,  # noqa: F821
        cases=snakemake.input.cases,  # noqa: F821
        bands=snakemake.input.bands,  # noqa: F821
        results_dir="results",
        example=snakemake.params.example,  # noqa: F821
        analysis=json.loads(snakemake.params.analysis),  # noqa: F821
        outdir=snakemake.output[0],  # noqa: F821
    )
    print("\n".join(map(str, written)), file=log)
