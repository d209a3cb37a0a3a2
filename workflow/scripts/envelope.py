"""Rule envelope: raw spectrum and envelope harmonics of one case for every band."""
from bearing_envelope.io import read_bands, read_case, write_spectra, write_tidy
from bearing_envelope.study.pipeline import case_envelope
from bearing_envelope.study.provenance import log_to
from bearing_envelope.study.job_transport import job_settings

with log_to(snakemake.log[0]):  # noqa: F821
    inp, out = snakemake.input, snakemake.output  # noqa: F821
    table, spectra = case_envelope(read_case(inp.case), job_settings(snakemake).analysis,  # noqa: F821
                                   read_bands(inp.bands))
    write_tidy(out.harmonics, table, sealed=True)  # digest: an edit is refused by aggregate
    write_spectra(out.spectra, spectra)
