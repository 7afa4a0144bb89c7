// SPDX-License-Identifier: MIT
#include "VideoWriter.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <fcntl.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

namespace bsdeform {

namespace {
std::string avError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}

std::string extensionOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}
}  // namespace

struct VideoWriter::Impl {
  std::string path, temporary;
  int sourceWidth = 0;  // of the RGB frames given
  std::vector<uint8_t> staging;  // the frame's rows at stagingStride, padded for swscale
  int stagingStride = 0;
  AVFormatContext* format = nullptr;
  AVCodecContext* codec = nullptr;
  AVStream* stream = nullptr;
  AVFrame* frame = nullptr;
  AVPacket* packet = nullptr;
  SwsContext* scale = nullptr;
  long long frames = 0;
  bool finished = false;

  ~Impl() {
    if (scale) sws_freeContext(scale);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&codec);
    if (format) {
      if (format->pb) avio_closep(&format->pb);
      avformat_free_context(format);
    }
    if (!finished && !temporary.empty()) std::remove(temporary.c_str());
  }

  std::string fail(const std::string& what, int code) const {
    return "cannot write '" + path + "': " + what + (code ? ": " + avError(code) : std::string());
  }

  /// Sends a frame (null: the end) and writes every packet the encoder gives back.
  bool encode(AVFrame* f, std::string& error) {
    int r = avcodec_send_frame(codec, f);
    if (r < 0) {
      error = fail("encoding failed", r);
      return false;
    }
    while ((r = avcodec_receive_packet(codec, packet)) >= 0) {
      av_packet_rescale_ts(packet, codec->time_base, stream->time_base);
      packet->stream_index = stream->index;
      r = av_interleaved_write_frame(format, packet);  // takes the packet's data
      if (r < 0) {
        error = fail("writing failed", r);
        return false;
      }
    }
    if (r != AVERROR(EAGAIN) && r != AVERROR_EOF) {
      error = fail("encoding failed", r);
      return false;
    }
    return true;
  }
};

VideoWriter::VideoWriter() : m(std::make_unique<Impl>()) {}
VideoWriter::~VideoWriter() = default;

std::unique_ptr<VideoWriter> VideoWriter::open(const std::string& path, int width, int height, double fps,
                                               std::string& error) {
  av_log_set_level(AV_LOG_ERROR);  // the encoders' statistics are not for our users' terminals
  std::unique_ptr<VideoWriter> w(new VideoWriter);
  Impl& m = *w->m;
  m.path = path;
  const std::string ext = extensionOf(path);
  AVCodecID codecId;
  if (ext == ".mp4")
    codecId = AV_CODEC_ID_H264;
  else if (ext == ".webm")
    codecId = AV_CODEC_ID_VP9;
  else {
    error = "cannot write '" + path + "': the extension '" + ext + "' is not a video this program writes (.mp4 or .webm)";
    return nullptr;
  }
  const int evenWidth = width & ~1, evenHeight = height & ~1;
  if (evenWidth < 2 || evenHeight < 2 || width > 16384 || height > 16384) {
    error = "cannot write '" + path + "': frame size " + std::to_string(width) + " x " + std::to_string(height) +
            " out of 2..16384";
    return nullptr;
  }
  if (!(fps > 0.0) || fps > 1000.0) {
    error = "cannot write '" + path + "': frame rate " + std::to_string(fps) + " out of (0, 1000]";
    return nullptr;
  }
  const AVCodec* encoder = avcodec_find_encoder(codecId);
  if (!encoder) {
    error = "cannot write '" + path + "': this FFmpeg has no " + avcodec_get_name(codecId) + " encoder";
    return nullptr;
  }
  const AVOutputFormat* container = av_guess_format(nullptr, path.c_str(), nullptr);
  // beside the target (the same file system: the rename is atomic), hidden, one per process;
  // created by avio_open with the permissions the user's umask gives
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  m.temporary = dir + "." + name + "." + std::to_string(::getpid()) + ".part";

  int r = avformat_alloc_output_context2(&m.format, container, nullptr, m.temporary.c_str());
  if (r < 0 || !m.format) {
    error = m.fail("no container", r);
    return nullptr;
  }
  m.stream = avformat_new_stream(m.format, nullptr);
  m.codec = avcodec_alloc_context3(encoder);
  m.frame = av_frame_alloc();
  m.packet = av_packet_alloc();
  if (!m.stream || !m.codec || !m.frame || !m.packet) {
    error = m.fail("out of memory", 0);
    return nullptr;
  }
  const AVRational rate = av_d2q(fps, 100000);
  m.codec->width = evenWidth;
  m.codec->height = evenHeight;
  m.codec->time_base = av_inv_q(rate);
  m.codec->framerate = rate;
  m.codec->pix_fmt = AV_PIX_FMT_YUV420P;
  m.codec->gop_size = 2 * int(std::ceil(fps));  // a key frame every two seconds: seekable
  if (m.format->oformat->flags & AVFMT_GLOBALHEADER) m.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
  if (codecId == AV_CODEC_ID_H264) {
    av_opt_set(m.codec->priv_data, "preset", "veryfast", 0);
    av_opt_set(m.codec->priv_data, "crf", "18", 0);  // visually lossless for smooth shading
  } else {
    av_opt_set(m.codec->priv_data, "deadline", "realtime", 0);
    av_opt_set(m.codec->priv_data, "cpu-used", "8", 0);
    av_opt_set(m.codec->priv_data, "crf", "24", 0);
    m.codec->bit_rate = 0;  // constant quality
  }
  r = avcodec_open2(m.codec, encoder, nullptr);
  if (r < 0) {
    error = m.fail(std::string("cannot open the ") + encoder->name + " encoder", r);
    return nullptr;
  }
  r = avcodec_parameters_from_context(m.stream->codecpar, m.codec);
  if (r < 0) {
    error = m.fail("codec parameters", r);
    return nullptr;
  }
  m.stream->time_base = m.codec->time_base;
  m.stream->avg_frame_rate = rate;
  r = avio_open(&m.format->pb, m.temporary.c_str(), AVIO_FLAG_WRITE);
  if (r < 0) {
    error = m.fail("cannot open the temporary file", r);
    return nullptr;
  }
  r = avformat_write_header(m.format, nullptr);
  if (r < 0) {
    error = m.fail("cannot write the header", r);
    return nullptr;
  }
  m.frame->format = m.codec->pix_fmt;
  m.frame->width = evenWidth;
  m.frame->height = evenHeight;
  r = av_frame_get_buffer(m.frame, 0);
  if (r < 0) {
    error = m.fail("frame buffer", r);
    return nullptr;
  }
  // RGB to YUV 4:2:0 (BT.601, limited range: what players assume when nothing is said)
  m.scale = sws_getContext(evenWidth, evenHeight, AV_PIX_FMT_RGB24, evenWidth, evenHeight, AV_PIX_FMT_YUV420P,
                           SWS_BICUBIC, nullptr, nullptr, nullptr);
  if (!m.scale) {
    error = m.fail("no RGB to YUV conversion", 0);
    return nullptr;
  }
  m.sourceWidth = width;
  m.stagingStride = (3 * evenWidth + 63) / 64 * 64;
  m.staging.assign(size_t(m.stagingStride) * evenHeight + 64, 0);
  return w;
}

bool VideoWriter::addFrame(const unsigned char* rgb, std::string& error, int rowBytes) {
  if (m->finished || !rgb) {
    error = "cannot write '" + m->path + "': " + (m->finished ? "the video is already finished" : "no frame");
    return false;
  }
  const int r = av_frame_make_writable(m->frame);
  if (r < 0) {
    error = m->fail("frame buffer", r);
    return false;
  }
  // swscale's SIMD reads whole blocks past the end of a row: hand it rows in a padded, aligned
  // copy (the odd column, if any, is left out)
  const int w = m->codec->width, h = m->codec->height;
  const size_t row = rowBytes > 0 ? size_t(rowBytes) : size_t(3) * size_t(m->sourceWidth);
  for (int y = 0; y < h; ++y)
    std::memcpy(m->staging.data() + size_t(y) * m->stagingStride, rgb + size_t(y) * row, size_t(3 * w));
  const uint8_t* planes[1] = {m->staging.data()};
  const int strides[1] = {m->stagingStride};
  sws_scale(m->scale, planes, strides, 0, h, m->frame->data, m->frame->linesize);
  m->frame->pts = m->frames;
  if (!m->encode(m->frame, error)) return false;
  ++m->frames;
  return true;
}

bool VideoWriter::finish(std::string& error) {
  if (m->finished) return true;
  if (!m->encode(nullptr, error)) return false;
  int r = av_write_trailer(m->format);
  if (r < 0) {
    error = m->fail("cannot write the trailer", r);
    return false;
  }
  r = avio_closep(&m->format->pb);  // reports a failed final flush (a full disk)
  if (r < 0) {
    error = m->fail("cannot close", r);
    return false;
  }
  const int fd = ::open(m->temporary.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const int syncErrno = errno;
  if (fd >= 0) ::close(fd);
  if (!synced) {
    error = "cannot write '" + m->path + "': " + std::strerror(syncErrno);
    return false;
  }
  if (std::rename(m->temporary.c_str(), m->path.c_str()) != 0) {
    error = "cannot write '" + m->path + "': " + std::strerror(errno);
    return false;
  }
  m->finished = true;
  return true;
}

int VideoWriter::width() const { return m->codec->width; }
int VideoWriter::height() const { return m->codec->height; }
long long VideoWriter::frames() const { return m->frames; }
const std::string& VideoWriter::path() const { return m->path; }

}  // namespace bsdeform
