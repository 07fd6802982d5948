"""Sensor models: AMCW ToF camera and FMCW radar front end."""
