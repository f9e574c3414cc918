"""The acoustic model: what is heard in 10 ms of speech, learnt from people's voices and eSpeak NG's.

features.py describes the audio (log mel bands levelled on the take's own speech), network.py runs the
trained network with numpy alone (its weights beside it come from lab/train/recogniser.py: eSpeak NG's
Turkish voice and recordings of people), labels.py names its classes (the Turkish letters that are sounds,
and silence), forced.py finds where each letter of a known text lies. The recording aligner, the speech
detector and the audio-only recogniser all hear through it. whisper.py is the audio-only recogniser's
second hearing: Whisper tiny's encoder, which has heard many people, under a classifier of the same
classes (its weights from lab/train/whisper_head.py).
"""
