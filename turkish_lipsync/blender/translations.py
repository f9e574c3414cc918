"""Turkish UI: Blender shows these when its interface language is Turkish (tr_TR)."""

from __future__ import annotations

import bpy

from ..core.faces.arkit_names import ARKIT_UNITS
from ..core.faces.rig_poses import pose_target_label, pose_targets

LOCALE = "tr_TR"

# English UI text -> Turkish. Labels, headings, enum items, tooltips of properties and operators.
TURKISH = {
    # panel and headings
    "Turkish Lip Sync": "Türkçe Dudak Senkronu",
    "Lip Sync": "Dudak Senkronu",
    "Head": "Kafa",
    "Speech": "Konuşma",
    "Render": "Görüntü Oluşturma",
    "Export": "Dışa Aktar",
    "Key Sources": "Anahtarların Kaynakları",
    # operators
    "Build Shape Keys": "Şekil Anahtarlarını Oluştur",
    "Generate Animation": "Animasyonu Üret",
    "Render Video": "Videoyu Oluştur",
    "Show Landmarks": "Yüz İşaretlerini Göster",
    "Clear Landmarks": "Yüz İşaretlerini Temizle",
    "Build the Turkish viseme and emotion shape keys on the head (the reference head when none is chosen)": (
        "Kafaya Türkçe vizem ve duygu şekil anahtarlarını kurar (kafa seçilmemişse referans kafayı ekler)"
    ),
    "Speak the text: key the head's mouth shapes and emotions, and put the speech in the sequencer": (
        "Metni seslendirir: ağız şekillerini ve duyguları anahtarlar, konuşmayı kurgu düzenleyicisine koyar"
    ),
    "Render the frame range to an MP4 with the speech, adding a camera and lights on the face if missing": (
        "Sahnenin kare aralığını konuşmayla birlikte MP4 olarak oluşturur; eksikse yüze kamera ve ışık ekler"
    ),
    "Find the face landmarks on the head and show them as markers to move where they are off": (
        "Kafadaki yüz işaretlerini bulur ve yanlış olanları taşıyabilmeniz için işaretçi olarak gösterir"
    ),
    "Remove the head's landmark markers: the next build finds the landmarks automatically again": (
        "Kafanın yüz işaretçilerini kaldırır: sonraki oluşturma yüz işaretlerini yeniden kendiliğinden bulur"
    ),
    # poll messages
    "Switch to Object Mode first": "Önce Nesne Kipine geçin",
    "Choose the head object in the Lip Sync panel": "Dudak Senkronu panelinde kafa nesnesini seçin",
    "The head has no lip-sync shape keys yet: build them first": (
        "Kafada henüz dudak senkronu şekil anahtarı yok: önce onları oluşturun"
    ),
    "Choose the Text to speak in the Lip Sync panel": "Dudak Senkronu panelinde seslendirilecek metni seçin",
    "Choose the JSML file to speak in the Lip Sync panel": (
        "Dudak Senkronu panelinde seslendirilecek JSML dosyasını seçin"
    ),
    "Choose the video file to write in the Lip Sync panel": (
        "Dudak Senkronu panelinde yazılacak video dosyasını seçin"
    ),
    "Choose the head (to frame a camera on it) or add a camera": (
        "Kafayı seçin (kamera ona göre yerleştirilir) ya da bir kamera ekleyin"
    ),
    "Choose the folder of OBJ models in the Lip Sync panel": (
        "Dudak Senkronu panelinde OBJ modellerinin klasörünü seçin"
    ),
    "Choose a head with its own ARKit shape keys (the reference head has none)": (
        "Kendi ARKit şekil anahtarları olan bir kafa seçin (referans kafada bunlar yok)"
    ),
    "Table timing uses no speech, so it cannot follow a recording: choose Phone or Word timing": (
        "Tablo zamanlaması konuşma kullanmaz, bu yüzden bir kayda uyamaz: Ses ya da Sözcük "
        "zamanlamasını seçin"
    ),
    "The head has no landmark markers": "Kafada yüz işaretçisi yok",
    # properties
    "The head mesh that speaks; its teeth, tongue and eyes follow it": (
        "Konuşan kafa ağı; dişleri, dili ve gözleri onu izler"
    ),
    "Source": "Kaynak",
    "Where the Turkish text (plain or JSML markup) comes from": "Türkçe metnin (düz ya da JSML) kaynağı",
    "Text": "Metin",
    "A Text datablock of this file (Text Editor)": "Bu dosyadaki bir metin bloğu (Metin Düzenleyici)",
    "File": "Dosya",
    "A JSML or plain-text file on disk": "Diskte bir JSML ya da düz metin dosyası",
    "Turkish text, plain or JSML markup": "Türkçe metin, düz ya da JSML işaretlemeli",
    "A UTF-8 file with Turkish text, plain or JSML markup": "Türkçe metin içeren UTF-8 dosya, düz ya da JSML",
    "Timing": "Zamanlama",
    "How the mouth shapes are timed against the speech": "Ağız şekillerinin konuşmaya göre zamanlanması",
    "Phone": "Ses",
    "Key every phone where the speech engine speaks it (most accurate)": (
        "Her sesi, konuşma motorunun onu söylediği anda anahtarlar (en doğru)"
    ),
    "Word": "Sözcük",
    "The thesis's method: word starts from the engine, letters by mean durations": (
        "Tezin yöntemi: sözcük başlangıçları motordan, harfler ortalama sürelerle"
    ),
    "Table": "Tablo",
    "Mean letter durations only (thesis Table 5.4), no speech engine, no audio": (
        "Yalnızca ortalama harf süreleri (tez Tablo 5.4); konuşma motoru ve ses yok"
    ),
    "Speaking Rate": "Konuşma Hızı",
    "Multiplier of the speaking rate (1 is the engine's normal speed)": (
        "Konuşma hızı çarpanı (1, motorun normal hızıdır)"
    ),
    "Emotion Strength": "Duygu Şiddeti",
    "How strongly the emotions of the markup show on the face": (
        "İşaretlemedeki duyguların yüzde ne kadar güçlü görüneceği"
    ),
    "Motion": "Hareket",
    "How the weights move between mouth shapes": "Ağırlıkların ağız şekilleri arasında nasıl geçtiği",
    "Natural": "Doğal",
    "Co-articulation, hard lip closures and layered emotions": (
        "Eşsesletim, tam dudak kapanmaları ve katmanlı duygular"
    ),
    "Thesis": "Tez",
    "The thesis's weighted morphing from letter to letter (eq. 5.3, 5.4)": (
        "Tezin harften harfe ağırlıklı biçim dönüşümü (denklem 5.3, 5.4)"
    ),
    "Interpolation": "Ara Değerleme",
    "Interpolation of the shape-key keyframes": "Şekil anahtarı karelerinin ara değerlemesi",
    "Automatic": "Otomatik",
    "What the motion model asks for": "Hareket modelinin istediği",
    "Linear": "Doğrusal",
    "Straight lines between keys": "Anahtarlar arasında düz çizgiler",
    "Bézier": "Bézier",
    "Smooth curves between keys": "Anahtarlar arasında yumuşak eğriler",
    "Constant": "Sabit",
    "Hold each key until the next (stepped)": "Her anahtarı bir sonrakine kadar tutar (basamaklı)",
    "Keep ARKit Keys": "ARKit Anahtarlarını Tut",
    "Also keep the 52 ARKit face-unit shape keys the mouth shapes are built from": (
        "Ağız şekillerinin kurulduğu 52 ARKit yüz birimi şekil anahtarını da tutar"
    ),
    "Shape-Key Source": "Şekil Anahtarı Kaynağı",
    "What the mouth shapes and emotions are built from": "Ağız şekillerinin ve duyguların neyden kurulacağı",
    "Auto": "Otomatik",
    "The head's own visemes or ARKit keys, else a transfer from the reference head": (
        "Kafanın kendi vizemleri ya da ARKit anahtarları, yoksa referans kafadan bir aktarım"
    ),
    "Own Visemes": "Kendi Vizemleri",
    "The head's own visemes (Oculus, VRM, Azure, Papagayo) or those a mapping file names": (
        "Kafanın kendi vizemleri (Oculus, VRM, Azure, Papagayo) ya da bir eşleme dosyasının adlandırdıkları"
    ),
    "Mapping File": "Eşleme Dosyası",
    "Your own TOML file naming the head's keys for the Turkish visemes (empty: the keys are recognised by "
    "their names)": (
        "Türkçe vizemler için kafanın anahtarlarını adlandıran kendi TOML dosyanız "
        "(boş: anahtarlar adlarından tanınır)"
    ),
    "glTF File": "glTF Dosyası",
    "The .glb file Export glTF writes: the head, its shape keys and the speech animation (the speech WAV "
    "goes beside it)": (
        "glTF Dışa Aktar'ın yazdığı .glb dosyası: kafa, şekil anahtarları ve konuşma animasyonu "
        "(konuşmanın WAV dosyası yanına konur)"
    ),
    "Export glTF": "glTF Dışa Aktar",
    "Export the head, its shape keys and the speech animation as .glb, the speech WAV beside it": (
        "Kafayı, şekil anahtarlarını ve konuşma animasyonunu .glb olarak dışa aktarır; konuşmanın WAV "
        "dosyası yanına konur"
    ),
    "Choose a head with visemes of its own (the reference head has none)": (
        "Kendi vizemleri olan bir kafa seçin (referans kafada bunlar yok)"
    ),
    "Generate the animation first: the head has no speech to export": (
        "Önce animasyonu üretin: kafada dışa aktarılacak konuşma yok"
    ),
    "Choose the glTF file to write in the Lip Sync panel": (
        "Dudak Senkronu panelinde yazılacak glTF dosyasını seçin"
    ),
    "Own ARKit Keys": "Kendi ARKit Anahtarları",
    "Build from the head's own ARKit-named shape keys (jawOpen, ...)": (
        "Kafanın kendi ARKit adlı şekil anahtarlarından kurar (jawOpen, ...)"
    ),
    "Transfer from Reference": "Referanstan Aktar",
    "Carry the reference head's face units over, registered with the face landmarks": (
        "Referans kafanın yüz birimlerini yüz işaretleriyle hizalayarak bu kafaya aktarır"
    ),
    "Folder of OBJ Models": "OBJ Modelleri Klasörü",
    "The thesis's way: one homeomorphic OBJ model per viseme (a.obj, bpa.obj, ..., Neutral.obj)": (
        "Tezin yolu: her vizem için bir homeomorfik OBJ modeli (a.obj, bpa.obj, ..., Neutral.obj)"
    ),
    "OBJ Folder": "OBJ Klasörü",
    "The head's OBJ models, same vertices in the same order (a.obj, ..., Neutral.obj)": (
        "Kafanın OBJ modelleri; aynı köşeler, aynı sırada (a.obj, ..., Neutral.obj)"
    ),
    "Empowered Emotions": "Güçlendirilmiş Duygular",
    "Store the emotion keys exaggerated by the empowering constant (thesis eq. 5.2), for "
    "keying them by hand; generated animation needs plain keys (its thesis mode empowers by itself)": (
        "Duygu anahtarlarını güçlendirme katsayısıyla abartılmış olarak saklar (tez denklem 5.2); elle "
        "anahtarlamak içindir. Üretilen animasyon düz anahtarlar ister (tez kipi güçlendirmeyi kendisi yapar)"
    ),
    "Empowering Constant": "Güçlendirme Katsayısı",
    "How many times stronger the empowered emotions are (ρ in the thesis, which uses 3)": (
        "Güçlendirilmiş duyguların kaç kat daha güçlü olduğu (tezdeki ρ; tez 3 kullanır)"
    ),
    "Own Recording": "Kendi Kaydınız",
    "Your own recording of the same text (WAV, FLAC, OGG, MP3, M4A, or the sound of a video: "
    "MP4, MOV, MKV, WebM): the mouth follows it and it becomes the sound (empty: the synthetic voice). "
    "With no text, what it says is recognised (a few seconds for each minute of speech)": (
        "Aynı metni okuduğunuz kendi kaydınız (WAV, FLAC, OGG, MP3, M4A ya da bir videonun sesi: MP4, MOV, "
        "MKV, WebM): ağız ona uyar ve ses olarak o kullanılır (boş: yapay ses). Metin yoksa kaydın "
        "söyledikleri sesten tanınır (her dakikalık konuşma için birkaç saniye)"
    ),
    "Choose Recording": "Kayıt Seç",
    "Browse for a recording: WAV, FLAC, OGG, MP3, M4A or AAC, or a video with sound (MP4, MOV, MKV, "
    "WebM); only these are shown": (
        "Bir kayıt seçin: WAV, FLAC, OGG, MP3, M4A ya da AAC veya sesli bir video (MP4, MOV, MKV, WebM); "
        "yalnızca bunlar gösterilir"
    ),
    "Relative Path": "Göreli Yol",
    "Store the path relative to the saved .blend file, so the two can move together": (
        "Yolu kayıtlı .blend dosyasına göre saklar; ikisi birlikte taşınabilir"
    ),
    "Choose a speaker in the cast first": "Önce oyunculardan bir konuşmacı seçin",
    "Audio Folder": "Ses Klasörü",
    "Where the speech WAV is saved (empty: a folder next to the saved .blend file)": (
        "Konuşma WAV dosyasının kaydedileceği yer (boş: kayıtlı .blend dosyasının yanındaki bir klasör)"
    ),
    "Render Engine": "Oluşturma Motoru",
    # engine names are proper names, as in Blender's own Turkish UI
    "EEVEE": "EEVEE",
    "Cycles": "Cycles",
    "Workbench": "Workbench",
    "The engine that renders the video": "Videoyu oluşturan motor",
    "EEVEE where OpenGL is available, Cycles otherwise": "OpenGL varsa EEVEE, yoksa Cycles",
    "Fast, needs OpenGL": "Hızlı, OpenGL gerektirir",
    "Path tracing on the CPU, works everywhere": "İşlemcide ışın izleme, her yerde çalışır",
    "Solid shading preview, needs OpenGL": "Düz gölgeli önizleme, OpenGL gerektirir",
    "Samples": "Örnek Sayısı",
    "Render samples per pixel (EEVEE and Cycles)": "Piksel başına örnek sayısı (EEVEE ve Cycles)",
    "Video": "Video",
    "The MP4 file to write (H.264 video with AAC audio)": "Yazılacak MP4 dosyası (H.264 görüntü, AAC ses)",
    # timing from cue files, and exports for other tools
    "Cue File": "Zamanlama Dosyası",
    "A Rhubarb (.tsv, .json, .xml), Papagayo (.pgo) or Moho (.dat) file that times the mouth "
    "shapes instead of the speech engine; the recording is then its sound; a .pgo brings its text": (
        "Ağız şekillerini konuşma motoru yerine zamanlayan Rhubarb (.tsv, .json, .xml), Papagayo (.pgo) "
        "veya Moho (.dat) dosyası; kayıt o zaman sesi olur; .pgo kendi metnini getirir"
    ),
    "Format": "Biçim",
    "What Export Animation writes, and for which tools": (
        "Animasyonu Dışa Aktar'ın neyi, hangi araçlar için yazdığı"
    ),
    "Export File": "Dışa Aktarma Dosyası",
    "The file Export Animation writes; its extension follows the format": (
        "Animasyonu Dışa Aktar'ın yazdığı dosya; uzantısı biçime göre belirlenir"
    ),
    "Export Animation": "Animasyonu Dışa Aktar",
    "Write the speech for other tools: Rhubarb mouth cues, Moho switch data, Papagayo or ARKit CSV": (
        "Konuşmayı diğer araçlar için yazar: Rhubarb ağız işaretleri, Moho anahtar verisi, Papagayo ya da "
        "ARKit CSV"
    ),
    "Choose the file to export to in the Lip Sync panel": (
        "Dudak Senkronu panelinde dışa aktarılacak dosyayı seçin"
    ),
    "Save the .blend first, or choose an absolute path to export to": (
        "Önce .blend dosyasını kaydedin ya da dışa aktarmak için tam bir yol seçin"
    ),
    # format names are proper names
    "Rhubarb TSV": "Rhubarb TSV",
    "Rhubarb JSON": "Rhubarb JSON",
    "Rhubarb XML": "Rhubarb XML",
    "Moho Switch Data": "Moho Anahtar Verisi",
    "Papagayo Project": "Papagayo Projesi",
    "ARKit CSV": "ARKit CSV",
    "Mouth cues A-H and X with their start times (Rhubarb Lip Sync)": (
        "Başlangıç zamanlarıyla A-H ve X ağız işaretleri (Rhubarb Lip Sync)"
    ),
    "Mouth cues A-H and X as JSON (Godot, Unity, Spine, web players)": (
        "JSON olarak A-H ve X ağız işaretleri (Godot, Unity, Spine, web oynatıcıları)"
    ),
    "Mouth cues A-H and X as XML (Rhubarb Lip Sync's XML output)": (
        "XML olarak A-H ve X ağız işaretleri (Rhubarb Lip Sync'in XML çıktısı)"
    ),
    "Preston Blair mouths per frame for Moho and OpenToonz (.dat)": (
        "Moho ve OpenToonz için kare kare Preston Blair ağızları (.dat)"
    ),
    "Words and mouths per frame for Papagayo-NG (.pgo)": (
        "Papagayo-NG için kare kare sözcükler ve ağızlar (.pgo)"
    ),
    "52 ARKit weights per frame, Live Link Face layout (Unreal, MetaHuman)": (
        "Her kare için 52 ARKit ağırlığı, Live Link Face düzeninde (Unreal, MetaHuman)"
    ),
    # preferences
    "eSpeak NG Library": "eSpeak NG Kitaplığı",
    "A libespeak-ng to use instead of the bundled one (empty: bundled, then the system's)": (
        "Paketle gelen yerine kullanılacak libespeak-ng kitaplığı (boş: paketteki, sonra sistemdeki)"
    ),
    "eSpeak NG Data": "eSpeak NG Verisi",
    "The espeak-ng-data folder that belongs to that library (empty: the library's own)": (
        "O kitaplığa ait espeak-ng-data klasörü (boş: kitaplığın kendi verisi)"
    ),
    # the living face
    "Living Face": "Canlı Yüz",
    "As the motion has it: on for Natural, off for Thesis": "Harekete göre: Doğal'da açık, Tez'de kapalı",
    "On": "Açık",
    "On for either motion": "İki harekette de açık",
    "Off": "Kapalı",
    "Gaze": "Bakış",
    "Eyes that hold the camera (or the target) and look away with saccades": (
        "Kameraya (ya da hedefe) bakan ve sıçramalarla başka yöne bakan gözler"
    ),
    "Gaze Amount": "Bakış Miktarı",
    "How far the eyes look away (1 the usual)": "Gözlerin ne kadar uzağa baktığı (1 olağan)",
    "Blinks": "Göz Kırpma",
    "Blinks at pauses, phrase ends and large gaze shifts": (
        "Duraklarda, söz öbeği sonlarında ve büyük bakış kaymalarında göz kırpma"
    ),
    "Blink Amount": "Göz Kırpma Miktarı",
    "How often the eyes blink (1 about 17 a minute)": (
        "Gözlerin ne sıklıkla kırpıldığı (1 dakikada yaklaşık 17)"
    ),
    "Head Motion": "Baş Hareketi",
    "Nods, turns and tilts from the voice's pitch and loudness": (
        "Sesin perdesinden ve şiddetinden baş sallama, dönme ve eğilme"
    ),
    "Head Amount": "Baş Hareketi Miktarı",
    "How far the head moves (1 a few degrees)": "Başın ne kadar hareket ettiği (1 birkaç derece)",
    "Expression": "İfade",
    "Brows rising on pitch accents and emphasis, emotions that breathe at their apex": (
        "Perde vurgularında ve vurgulu sözcüklerde kalkan kaşlar, doruğunda canlı kalan duygular"
    ),
    "Expression Amount": "İfade Miktarı",
    "How strongly the brows and emotions live": "Kaşların ve duyguların ne kadar canlı olduğu",
    "Seed": "Tohum",
    "Another seed gives other glances, blinks and head moves": (
        "Başka bir tohum başka bakışlar, göz kırpmalar ve baş hareketleri verir"
    ),
    "Gaze Target": "Bakış Hedefi",
    "The object the eyes seek while talking (empty: the scene's camera)": (
        "Konuşurken gözlerin aradığı nesne (boş: sahnenin kamerası)"
    ),
    # a conversation: the cast
    "Conversation": "Karşılıklı Konuşma",
    "Fill Cast from Script": "Oyuncuları Metinden Doldur",
    "List the script's speakers in the cast, keeping what was chosen for those already listed": (
        "Metindeki konuşmacıları oyuncu listesine ekler; listede olanlar için seçilenleri korur"
    ),
    "Cast": "Oyuncular",
    "Who plays each speaker of a script with speakers, filled from the script": (
        "Konuşmacılı bir metinde her konuşmacıyı kimin oynadığı; metinden doldurulur"
    ),
    "Cast Row": "Oyuncu Satırı",
    "The speaker chosen in the cast list": "Oyuncu listesinde seçili konuşmacı",
    "The head that plays this speaker (empty: a default head of its own, in a tone of its own, standing "
    "beside the others)": (
        "Bu konuşmacıyı oynayan kafa (boş: kendi tonunda, ötekilerin yanında duran kendine ait bir "
        "varsayılan kafa)"
    ),
    "Gender": "Cinsiyet",
    "As the script says, else as the name says, else the gender the cast has fewest of": (
        "Metin ne diyorsa o; yoksa adın söylediği; o da yoksa oyuncular arasında en az olan cinsiyet"
    ),
    "Female": "Kadın",
    "Male": "Erkek",
    "A woman's voice": "Bir kadın sesi",
    "A man's voice": "Bir erkek sesi",
    "Whose voice the speaker gets when the voice is Auto": (
        "Ses Otomatik olduğunda konuşmacının kimin sesini aldığı"
    ),
    "Voice": "Ses",
    "The speech engine's voice for this speaker": "Konuşma motorunun bu konuşmacı için sesi",
    "The cast's voice for the speaker's gender, distinct from the others'": (
        "Oyuncuların konuşmacının cinsiyetine göre seçtiği, ötekilerden farklı ses"
    ),
    "A woman's voice: a variant of eSpeak NG's Turkish voice": (
        "Bir kadın sesi: eSpeak NG'nin Türkçe sesinin bir çeşidi"
    ),
    "A man's voice: a variant of eSpeak NG's Turkish voice": (
        "Bir erkek sesi: eSpeak NG'nin Türkçe sesinin bir çeşidi"
    ),
    "Voice Pitch": "Ses Perdesi",
    "Multiplier of the chosen voice's pitch (with an Auto voice, the cast chooses it)": (
        "Seçilen sesin perdesinin çarpanı (ses Otomatik ise oyuncular seçer)"
    ),
    "Voice Rate": "Ses Hızı",
    "Multiplier of the chosen voice's speaking rate (with an Auto voice, the cast chooses it)": (
        "Seçilen sesin konuşma hızının çarpanı (ses Otomatik ise oyuncular seçer)"
    ),
    "How strongly this speaker's emotions show, times the Speech panel's Emotion Strength": (
        "Bu konuşmacının duygularının ne kadar güçlü göründüğü; Konuşma bölümündeki Duygu Şiddeti ile "
        "çarpılır"
    ),
    "Speaker Recording": "Konuşmacı Kaydı",
    "This speaker's track of the scene (WAV, FLAC, OGG, MP3, M4A, or a video's sound), "
    "starting where the scene starts and silent while the others speak; give one to every speaker, or "
    "one Own Recording of the whole scene": (
        "Bu konuşmacının sahnedeki kaydı (WAV, FLAC, OGG, MP3, M4A ya da bir videonun sesi): sahneyle "
        "birlikte başlar, ötekiler konuşurken sessizdir; her konuşmacıya bir tane verin ya da bütün sahnenin "
        "tek bir Kendi Kaydı'nı"
    ),
    "Line Recordings": "Satır Kayıtları",
    "A folder of recordings, one per line of the script, in the order of their file names (empty: the lines "
    "are synthesised, or the Own Recording holds the whole scene)": (
        "Metnin her satırı için bir kayıt içeren, dosya adlarının sırasıyla okunan bir klasör (boş: satırlar "
        "sentezlenir ya da Kendi Kaydı bütün sahneyi tutar)"
    ),
    # the face rig and linked characters
    "Face Rig": "Yüz Donanımı",
    "Use Face Rig": "Yüz Donanımını Kullan",
    "Stop Using Face Rig": "Yüz Donanımını Bırak",
    "Record Pose": "Pozu Kaydet",
    "Record from Action": "Eylemden Kaydet",
    "Clear Pose": "Pozu Temizle",
    "Make Keys Linkable": "Anahtarları Bağlanabilir Yap",
    "Keep the chosen face-rig mapping with the head's armature: Generate then moves its bones": (
        "Seçilen yüz donanımı eşlemesini kafanın iskeletinde saklar: Üret artık onun kemiklerini oynatır"
    ),
    "Remove the face-rig set-up and its recorded poses from the armature, and the rig's speech keys": (
        "Yüz donanımı ayarını ve kaydedilmiş pozlarını iskeletten, donanımın konuşma anahtarlarını da "
        "kaldırır"
    ),
    "Record the armature's current pose as the pose of the chosen viseme, emotion or ARKit unit": (
        "İskeletin şimdiki pozunu seçilen vizemin, duygunun ya da ARKit biriminin pozu olarak kaydeder"
    ),
    "Record the pose the Pose Action (or pose asset) holds at the Pose Frame as the chosen target's pose": (
        "Poz Eylemi'nin (ya da poz varlığının) Poz Karesi'ndeki pozunu seçilen hedefin pozu olarak kaydeder"
    ),
    "Forget this recorded pose (the mapping's own pose of its target, if any, is used again)": (
        "Bu kaydedilmiş pozu unutur (eşlemenin bu hedef için kendi pozu varsa yeniden o kullanılır)"
    ),
    "Drive the head's lip-sync keys by its own properties, so that shots that link it can animate them": (
        "Kafanın dudak senkronu anahtarlarını kendi özellikleriyle sürer; onu bağlayan çekimler de onları "
        "canlandırabilir"
    ),
    "The poses of the head's armature that make the visemes and emotions (Use Face Rig keeps the choice "
    "with the character)": (
        "Kafanın iskeletinde vizemleri ve duyguları oluşturan pozlar (Yüz Donanımını Kullan seçimi "
        "karakterle "
        "birlikte saklar)"
    ),
    "Jaw Bone": "Çene Kemiği",
    "The armature's bone that opens the jaw, for the Jaw Bone mapping (empty: found by its name)": (
        "Çene Kemiği eşlemesi için iskeletin çeneyi açan kemiği (boş: adından bulunur)"
    ),
    "One bone opens and closes the jaw; the lips follow it (game characters)": (
        "Çeneyi tek bir kemik açıp kapatır; dudaklar onu izler (oyun karakterleri)"
    ),
    "Rigify Face": "Rigify Yüzü",
    "Rigify's face rig: jaw, lip, lid and brow controls (generated from the human meta-rig)": (
        "Rigify'ın yüz donanımı: çene, dudak, göz kapağı ve kaş denetimleri (insan meta iskeletinden "
        "üretilir)"
    ),
    "Own Poses": "Kendi Pozları",
    "Only the poses recorded for this character below": "Yalnızca aşağıda bu karakter için kaydedilen pozlar",
    "Pose For": "Pozun Hedefi",
    "What the recorded pose stands for: a viseme, an emotion, a blink or look, or one of the 52 ARKit "
    "units": (
        "Kaydedilen pozun neyi karşıladığı: bir vizem, bir duygu, göz kırpma ya da bakış, veya 52 ARKit "
        "biriminden biri"
    ),
    "The target whose recorded pose is cleared": "Kaydedilmiş pozu temizlenecek hedef",
    "Pose Action": "Poz Eylemi",
    "An action or pose asset that holds a pose of the rig, for Record from Action": (
        "Eylemden Kaydet için donanımın bir pozunu tutan eylem ya da poz varlığı"
    ),
    "Pose Frame": "Poz Karesi",
    "The frame of the Pose Action that holds the pose": "Poz Eylemi'nde pozu tutan kare",
    "The head has no armature: give it an Armature modifier or an armature parent": (
        "Kafanın iskeleti yok: ona bir İskelet değiştiricisi ya da iskelet ebeveyni verin"
    ),
    "The armature is linked: set up its face rig in the character's own file": (
        "İskelet bağlı: yüz donanımını karakterin kendi dosyasında ayarlayın"
    ),
    "The armature has no face-rig set-up to remove": "İskelette kaldırılacak bir yüz donanımı ayarı yok",
    "Switch to Object or Pose Mode first": "Önce Nesne ya da Poz Kipine geçin",
    "Choose the Pose Action in the Face Rig section": "Yüz Donanımı bölümünde Poz Eylemi'ni seçin",
    "The head is linked: make its keys linkable in the character's own file": (
        "Kafa bağlı: anahtarlarını karakterin kendi dosyasında bağlanabilir yapın"
    ),
    "The head is linked and its library has no lip-sync keys or face rig yet: build them in the character's "
    "own file": (
        "Kafa bağlı ve kütüphanesinde henüz dudak senkronu anahtarı ya da yüz donanımı yok: onları "
        "karakterin "
        "kendi dosyasında oluşturun"
    ),
    "The head is linked and its keys are not linkable: press Make Keys Linkable in the character's own "
    "file": (
        "Kafa bağlı ve anahtarları bağlanabilir değil: karakterin kendi dosyasında Anahtarları Bağlanabilir "
        "Yap'a basın"
    ),
    "The head has no lip-sync shape keys or face rig yet: build the keys first": (
        "Kafada henüz dudak senkronu şekil anahtarı ya da yüz donanımı yok: önce anahtarları oluşturun"
    ),
}
# The cast's voices, numbered per gender as the panel lists them.
TURKISH |= {f"Female {number}": f"Kadın {number}" for number in range(1, 10)}
TURKISH |= {f"Male {number}": f"Erkek {number}" for number in range(1, 10)}

# The poses a face rig may record for ("Pose For", named as properties.py shows them): our keys in Turkish;
# ARKit's units keep their standard names, as every face tool shows them.
_EMOTIONS = {
    "happy": "mutlu",
    "sad": "üzgün",
    "angry": "kızgın",
    "afraid": "korkmuş",
    "surprised": "şaşırmış",
    "disgusted": "tiksinmiş",
}
_SIDES = {"left": "sol", "right": "sağ"}
_LOOKS = {"left": "sola", "right": "sağa", "up": "yukarı", "down": "aşağı"}
_POSE_NAMES = {
    "brow raise": "kaş kaldırma",
    **{f"blink {side}": f"{turkish} göz kırpma" for side, turkish in _SIDES.items()},
    **{
        f"eye {side} look {way}": f"{turkish} göz {towards} bakış"
        for side, turkish in _SIDES.items()
        for way, towards in _LOOKS.items()
    },
}


def _pose_name_in_turkish(name: str) -> str:
    kind, _, rest = name.partition(" ")
    if kind == "viseme":
        return f"vizem {rest}"
    if kind == "emotion":
        return f"duygu: {_EMOTIONS[rest]}"
    return name if name in ARKIT_UNITS else _POSE_NAMES[name]


TURKISH["A viseme, emotion, blink or look key, or an ARKit unit"] = (
    "Bir vizem, duygu, göz kırpma ya da bakış anahtarı, veya bir ARKit birimi"
)
TURKISH |= {label: _pose_name_in_turkish(label) for label in map(pose_target_label, pose_targets())}

# Operator labels are looked up in the "Operator" context, everything else in the default one.
_CONTEXTS = ("*", "Operator")


def translation_table() -> dict[str, dict[tuple[str, str], str]]:
    return {
        LOCALE: {(context, english): turkish for english, turkish in TURKISH.items() for context in _CONTEXTS}
    }


def register() -> None:
    bpy.app.translations.register(__package__, translation_table())


def unregister() -> None:
    bpy.app.translations.unregister(__package__)
