"""Options of the radar processing chain (:func:`simcore.dsp.process_frame`).

Every option has a default, so ``DspConfig()`` is a complete, working chain for the
BGT60TR13C-like preset: Hann range window, Chebyshev Doppler window zero-padded to twice
the number of chirps, Bartlett angle spectra over the actual antenna positions, 2-D
ordered-statistic CFAR on the non-coherently integrated range–Doppler map, local-maximum
peak grouping.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, model_validator

from simcore.scene.base import Model

WindowName = Literal["none", "hann", "hamming", "blackman", "blackmanharris", "chebyshev"]
"""Window families accepted by :func:`simcore.dsp.windows.make_window`."""

AngleMethod = Literal["monopulse", "fft", "bartlett", "capon"]
CfarMethod = Literal["ca", "go", "so", "os"]
PeakGrouping = Literal["none", "local_max", "cluster"]
SpectrogramMode = Literal["frame", "stft"]
StaticOffsetMethod = Literal["circle", "mean", "none"]
"""Static clutter / DC offset removal before the vital-sign phase (simcore.dsp.vitals)."""

RangeM = Annotated[float, Field(ge=0, le=1e5, allow_inf_nan=False)]
BandHz = Annotated[float, Field(ge=0, le=1e3, allow_inf_nan=False)]

#: Most grid angles of the azimuth or elevation search grid.
MAX_ANGLE_BINS = 3601


class DspConfig(Model):
    """Radar signal-processing options (units in the field names, SI otherwise).

    Range
        ``range_window`` (+ ``range_window_sidelobe_db`` for Chebyshev), ``remove_dc``
        (subtract each chirp's mean over fast time), ``range_fft_size`` (``None``: next
        power of two ≥ samples per chirp; larger values zero-pad), ``max_range_m`` (range
        bins beyond it are dropped from every product; ``None`` keeps all),
        ``min_range_m`` (detections closer than this are discarded: Tx→Rx leakage and the
        IF high-pass live there), ``interference_mitigation`` (``"zero"`` or
        ``"interpolate"`` the samples of interference bursts before the range FFT, found
        at ``interference_threshold`` robust sigmas; ``"off"``).
    Doppler
        ``doppler_window`` (Chebyshev by default, ``doppler_window_sidelobe_db`` sidelobe
        level), ``doppler_fft_size`` (``None``: twice the next power of two ≥ chirps per
        frame, i.e. 2× zero padding), ``static_clutter_removal`` (subtract the mean over
        chirps of every range bin: removes everything that does not move).
    Angle
        ``angle_method``: ``"monopulse"`` (phase difference of the closest horizontal and
        vertical element pairs), ``"fft"`` (zero-padded FFT over the uniform horizontal row
        of the virtual array, ``angle_fft_size`` points), ``"bartlett"`` or ``"capon"``
        (spectra over the actual virtual-element positions; ``capon_diagonal_loading`` is
        relative to the mean element power). The range–azimuth map uses Bartlett when the
        method is monopulse. The azimuth grid (``azimuth_*_deg``) is the axis of the
        range–azimuth map and the search grid of Bartlett/Capon; the elevation grid is
        searched only when the array has vertical extent. ``tdm_doppler_compensation``
        removes the Doppler phase that accrues between the Tx slots of a TDM-MIMO frame.
        ``angle_peaks_within_db``: targets in one range–Doppler cell that the array
        separates in azimuth are each a detection (further peaks of the Bartlett azimuth
        spectrum within that many dB of the largest; ``None``: one per cell).
    CFAR
        ``cfar_method`` (``"ca"`` cell averaging, ``"go"``/``"so"`` greatest-/smallest-of,
        ``"os"`` ordered statistic), ``cfar_dimensions`` (2: on the range–Doppler map;
        1: along range, row by row), guard and training cells on each side per axis,
        ``cfar_pfa`` the requested false-alarm probability per cell, ``cfar_os_rank`` the
        OS rank as a fraction of the number of training cells.
    Detections
        ``peak_grouping`` (``"local_max"``: a hit must be the maximum of its
        ``peak_neighbourhood`` (doppler, range) window of the map; ``"cluster"``: one hit per
        8-connected group of CFAR hits; ``"none"``), ``doppler_sidelobe_margin_db`` (a hit
        weaker than the strongest cell of its range bin by more than the Doppler window's
        peak sidelobe level minus this margin is a sidelobe and is dropped; ``None``
        disables), ``max_dynamic_range_db`` (cells weaker than the strongest cell of the
        map by more than this are never detections: only matters for noise-free cubes,
        whose float32 round-off floor sits ≈ 140 dB down; ``None`` disables),
        ``interpolate_peaks`` (parabolic
        sub-bin refinement of range and velocity), ``max_detections`` (strongest kept).
    Bird's-eye image
        ``bev_resolution_m`` pixel size of the Cartesian range–azimuth image.
    Micro-Doppler spectrogram (:mod:`simcore.dsp.microdoppler`)
        ``spectrogram_mode`` (``"frame"``: one Doppler spectrum per frame, any inter-frame
        gap; ``"stft"``: a short-time FFT over the chirps of consecutive frames,
        ``spectrogram_segment_chirps`` long (``None``: chirps per frame) with
        ``spectrogram_overlap``, segments never straddling a gap),
        ``spectrogram_window`` (+ ``spectrogram_window_sidelobe_db``),
        ``spectrogram_fft_size`` (``None``: 2× the next power of two ≥ the segment),
        ``spectrogram_clutter_removal`` (subtract each segment's mean: hides statics),
        ``spectrogram_range_m`` (the range gate, (min, max) m; ``None``: every bin beyond
        ``min_range_m``), ``spectrogram_history_s`` (columns kept by the live panel).
    Vital signs (:mod:`simcore.dsp.vitals`)
        ``vitals_breathing_band_hz`` and ``vitals_heart_band_hz`` (search bands),
        ``vitals_range_m`` (where to look for the chest, (min, max) m; ``None``: beyond
        ``min_range_m``), ``vitals_static_offset`` (``"circle"``: Kåsa circle-fit centre,
        ``"mean"``, ``"none"``), ``vitals_window`` of the rate spectra, ``vitals_channel``
        (virtual channel used), ``vitals_window_s`` (seconds of data per estimate).
    """

    # Range processing
    range_window: WindowName = "hann"
    range_window_sidelobe_db: float = Field(80.0, gt=0, le=300)
    remove_dc: bool = True
    range_fft_size: int | None = Field(None, ge=8, le=65536)
    max_range_m: float | None = Field(None, gt=0, le=1e5, allow_inf_nan=False)
    min_range_m: float = Field(0.2, ge=0, le=1e5, allow_inf_nan=False)

    interference_mitigation: Literal["off", "zero", "interpolate"] = Field(
        "off",
        description="radar interference bursts, before the range FFT: samples whose first "
                    "difference exceeds interference_threshold robust sigmas are zeroed or "
                    "interpolated (simcore.dsp.interference)")
    interference_threshold: float = Field(6.0, gt=0, le=1e3, allow_inf_nan=False)

    # Doppler processing
    doppler_window: WindowName = "chebyshev"
    doppler_window_sidelobe_db: float = Field(60.0, gt=0, le=300)
    doppler_fft_size: int | None = Field(None, ge=1, le=65536)
    static_clutter_removal: bool = False

    # Angle processing
    angle_method: AngleMethod = "bartlett"
    azimuth_min_deg: float = Field(-80.0, ge=-90, le=90)
    azimuth_max_deg: float = Field(80.0, ge=-90, le=90)
    azimuth_step_deg: float = Field(1.0, gt=0, le=45)
    elevation_min_deg: float = Field(-60.0, ge=-90, le=90)
    elevation_max_deg: float = Field(60.0, ge=-90, le=90)
    elevation_step_deg: float = Field(1.0, gt=0, le=45)
    angle_fft_size: int = Field(64, ge=2, le=4096)
    capon_diagonal_loading: float = Field(1e-3, ge=0, le=1e6, allow_inf_nan=False)
    tdm_doppler_compensation: bool = True
    angle_peaks_within_db: float | None = Field(
        6.0, ge=0, le=12,
        description="targets sharing a range–Doppler cell: every further peak of the "
                    "cell's Bartlett azimuth spectrum within this many dB of its largest "
                    "one is a detection of its own (None: one detection per cell)")

    # CFAR
    cfar_method: CfarMethod = "os"
    cfar_dimensions: Literal[1, 2] = 2
    cfar_guard_range: int = Field(2, ge=0, le=256)
    cfar_train_range: int = Field(8, ge=1, le=512)
    cfar_guard_doppler: int = Field(1, ge=0, le=256)
    cfar_train_doppler: int = Field(4, ge=0, le=512)
    cfar_pfa: float = Field(1e-6, gt=0, lt=1)
    cfar_os_rank: float = Field(0.75, gt=0, le=1)

    # Detections
    peak_grouping: PeakGrouping = "local_max"
    peak_neighbourhood: tuple[Annotated[int, Field(le=1001)], Annotated[int, Field(le=1001)]] = (
        3, 3)
    doppler_sidelobe_margin_db: float | None = Field(6.0, ge=-20, le=100)
    max_dynamic_range_db: float | None = Field(120.0, gt=0, le=400, allow_inf_nan=False)
    interpolate_peaks: bool = True
    max_detections: int = Field(256, ge=1, le=1_000_000)

    # Bird's-eye image
    bev_resolution_m: float = Field(0.05, ge=1e-4, le=100, allow_inf_nan=False)

    # Micro-Doppler spectrogram
    spectrogram_mode: SpectrogramMode = "frame"
    spectrogram_window: WindowName = "hann"
    spectrogram_window_sidelobe_db: float = Field(60.0, gt=0, le=300)
    spectrogram_segment_chirps: int | None = Field(None, ge=2, le=65536)
    spectrogram_overlap: float = Field(0.5, ge=0, lt=1)
    spectrogram_fft_size: int | None = Field(None, ge=2, le=65536)
    spectrogram_clutter_removal: bool = True
    spectrogram_range_m: tuple[RangeM, RangeM] | None = None
    spectrogram_history_s: float = Field(10.0, gt=0, le=3600, allow_inf_nan=False)

    # Vital signs
    vitals_breathing_band_hz: tuple[BandHz, BandHz] = (0.1, 0.6)
    vitals_heart_band_hz: tuple[BandHz, BandHz] = (0.8, 2.5)
    vitals_range_m: tuple[RangeM, RangeM] | None = None
    vitals_static_offset: StaticOffsetMethod = "circle"
    vitals_window: WindowName = "hann"
    vitals_channel: int = Field(0, ge=0, le=4095)
    vitals_window_s: float = Field(30.0, gt=0, le=3600, allow_inf_nan=False)

    @model_validator(mode="after")
    def _check(self) -> DspConfig:
        if self.azimuth_max_deg <= self.azimuth_min_deg:
            raise ValueError(
                f"azimuth_max_deg ({self.azimuth_max_deg}) must exceed azimuth_min_deg "
                f"({self.azimuth_min_deg})"
            )
        if self.elevation_max_deg <= self.elevation_min_deg:
            raise ValueError(
                f"elevation_max_deg ({self.elevation_max_deg}) must exceed elevation_min_deg "
                f"({self.elevation_min_deg})"
            )
        for axis in ("azimuth", "elevation"):
            lo, hi = getattr(self, f"{axis}_min_deg"), getattr(self, f"{axis}_max_deg")
            step = getattr(self, f"{axis}_step_deg")
            count = (hi - lo) / step + 1
            if count > MAX_ANGLE_BINS:
                raise ValueError(
                    f"{axis}_step_deg = {step:.3g}° gives {count:.3g} grid angles over "
                    f"[{lo}, {hi}]°; at most {MAX_ANGLE_BINS} (step >= "
                    f"{(hi - lo) / (MAX_ANGLE_BINS - 1):.3g}°)")
        if self.max_range_m is not None and self.min_range_m >= self.max_range_m:
            raise ValueError(
                f"min_range_m ({self.min_range_m}) must be below max_range_m "
                f"({self.max_range_m})")
        if any(n < 1 or n % 2 == 0 for n in self.peak_neighbourhood):
            raise ValueError(
                f"peak_neighbourhood must be odd sizes >= 1, got {self.peak_neighbourhood}"
            )
        for name in ("spectrogram_range_m", "vitals_range_m", "vitals_breathing_band_hz",
                     "vitals_heart_band_hz"):
            pair = getattr(self, name)
            if pair is not None and pair[1] <= pair[0]:
                raise ValueError(f"{name} = {tuple(pair)}: the upper end must exceed the lower")
        if self.cfar_dimensions == 2 and self.cfar_train_doppler < 1:
            raise ValueError("2-D CFAR needs cfar_train_doppler >= 1 (or use cfar_dimensions=1)")
        return self
